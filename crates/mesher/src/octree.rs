//! Top-down octree over the lattice that keeps only the bricks the surface can cross.
//!
//! A node is a cube of lattice cells. When the field's bound over the node's box is positive
//! the surface cannot cross it and the whole subtree is skipped; otherwise it is split into
//! eight until the brick size is reached. The field is 1-Lipschitz, so skipping is exact.

use rayon::prelude::*;

use crate::lattice::Lattice;
use crate::volume::Volume;

/// Cells along a brick's edge.
pub const BRICK: u64 = 4;

/// The order of the bricks: by their first cell's coordinate along the `sweep` axis, then in
/// (z, y, x) order. The polygonizer visits them slab by slab along that axis.
pub fn order_key(at: [u64; 3], sweep: usize) -> [u64; 4] {
    [at[sweep], at[2], at[1], at[0]]
}

/// Cells along the sweep axis of the octree's roots: the bricks are found one slab of this
/// thickness at a time, just ahead of the polygonizer's front, so that the list of active
/// bricks never covers the whole domain.
pub const THICK: u64 = 16 * BRICK;

/// Lattice cell coordinates of the first cell of every brick the surface may cross whose
/// coordinate along `sweep` lies in [from, from + [`THICK`]), in the order of [`order_key`], and
/// the number of field evaluations spent finding them. The roots are cubes of THICK cells
/// tiling that slab; subtrees are visited in parallel; the sort makes the result independent
/// of the thread count.
pub fn active_bricks<V: Volume>(
    field: &V,
    lattice: &Lattice,
    sweep: usize,
    from: u64,
) -> (Vec<[u64; 3]>, u64) {
    let cells = lattice.dims.map(|d| d - 1);
    let (a, b) = ((sweep + 1) % 3, (sweep + 2) % 3);
    let mut roots = Vec::new();
    for i in (0..cells[a]).step_by(THICK as usize) {
        for j in (0..cells[b]).step_by(THICK as usize) {
            let mut at = [0; 3];
            (at[sweep], at[a], at[b]) = (from, i, j);
            roots.push(at);
        }
    }
    let (mut bricks, evaluations) =
        roots.par_iter().map(|&at| visit(field, lattice, cells, at, THICK)).reduce(|| (Vec::new(), 0), merge);
    bricks.sort_unstable_by_key(|&b| order_key(b, sweep));
    (bricks, evaluations)
}

fn merge(mut acc: (Vec<[u64; 3]>, u64), (bricks, evaluations): (Vec<[u64; 3]>, u64)) -> (Vec<[u64; 3]>, u64) {
    acc.0.extend(bricks);
    acc.1 += evaluations;
    acc
}

/// Nodes at least this many cells wide split their children across threads.
const PARALLEL: u64 = 8 * BRICK;

fn visit<V: Volume>(
    field: &V,
    lattice: &Lattice,
    cells: [u64; 3],
    at: [u64; 3],
    size: u64,
) -> (Vec<[u64; 3]>, u64) {
    if (0..3).any(|a| at[a] >= cells[a]) {
        return (Vec::new(), 0);
    }
    let end = [0, 1, 2].map(|a| (at[a] + size).min(cells[a]));
    let lo = lattice.point(at);
    let hi = lattice.point(end);
    if field.bound(lo, hi) > 0.0 {
        return (Vec::new(), 1);
    }
    if size <= BRICK {
        return (vec![at], 1);
    }
    let half = size / 2;
    let children: Vec<[u64; 3]> = (0..8u64).map(|c| [0, 1, 2].map(|a| at[a] + half * (c >> a & 1))).collect();
    let visit_child = |&child: &[u64; 3]| visit(field, lattice, cells, child, half);
    let (bricks, evaluations) = if size >= PARALLEL {
        children.par_iter().map(visit_child).reduce(|| (Vec::new(), 0), merge)
    } else {
        children.iter().map(visit_child).fold((Vec::new(), 0), merge)
    };
    (bricks, evaluations + 1)
}
