//! Top-down octree over the lattice that keeps only the bricks the surface can cross.
//!
//! A node is a cube of lattice cells. When the field's bound over the node's box is positive
//! the surface cannot cross it and the whole subtree is skipped; otherwise it is split into
//! eight until the brick size is reached. The field is 1-Lipschitz, so skipping is exact. The
//! eight children of a node are bounded together ([`Volume::bounds`]), so that a field that
//! searches for its nearest primitive gathers the candidates near the node once for the eight.

use glam::DVec3;
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
    let (mut bricks, evaluations) = roots
        .par_iter()
        .map(|&at| {
            let mut found = Vec::new();
            let Some(node) = node_box(lattice, cells, at, THICK) else { return (found, 0) };
            if field.bound(node.0, node.1) > 0.0 {
                return (found, 1);
            }
            let evaluations = 1 + split(field, lattice, cells, (at, node), THICK, &mut found);
            (found, evaluations)
        })
        .reduce(|| (Vec::new(), 0), merge);
    bricks.par_sort_unstable_by_key(|&b| order_key(b, sweep));
    (bricks, evaluations)
}

fn merge(mut acc: (Vec<[u64; 3]>, u64), (bricks, evaluations): (Vec<[u64; 3]>, u64)) -> (Vec<[u64; 3]>, u64) {
    acc.0.extend(bricks);
    acc.1 += evaluations;
    acc
}

/// Nodes at least this many cells wide split their children across threads.
const PARALLEL: u64 = 8 * BRICK;

/// A node: its first cell and its box.
type Node = ([u64; 3], (DVec3, DVec3));

/// The box of the node of `size` cells at `at`, clipped to the lattice's cells; None when the
/// node lies beyond them.
fn node_box(lattice: &Lattice, cells: [u64; 3], at: [u64; 3], size: u64) -> Option<(DVec3, DVec3)> {
    if (0..3).any(|a| at[a] >= cells[a]) {
        return None;
    }
    let end = [0, 1, 2].map(|a| (at[a] + size).min(cells[a]));
    Some((lattice.point(at), lattice.point(end)))
}

/// Adds to `found` the bricks under `node` (of `size` cells, which the surface may cross): its
/// children are bounded together (one gathering of the field's candidates for the node's
/// box), and those the surface may cross are split in turn. Returns the evaluations spent.
fn split<V: Volume>(
    field: &V,
    lattice: &Lattice,
    cells: [u64; 3],
    (at, node): Node,
    size: u64,
    found: &mut Vec<[u64; 3]>,
) -> u64 {
    if size <= BRICK {
        found.push(at);
        return 0;
    }
    let half = size / 2;
    let mut children = [([0; 3], (DVec3::ZERO, DVec3::ZERO)); 8];
    let mut n = 0;
    for c in 0..8u64 {
        let child = [0, 1, 2].map(|a| at[a] + half * (c >> a & 1));
        if let Some(b) = node_box(lattice, cells, child, half) {
            children[n] = (child, b);
            n += 1;
        }
    }
    let boxes: [(DVec3, DVec3); 8] = std::array::from_fn(|c| children[c].1);
    let mut bounds = [0.0; 8];
    field.bounds(node.0, node.1, &boxes[..n], &mut bounds[..n]);
    // Kept unless the bound is positive (as a NaN bound is).
    let kept = |b: f64| b.partial_cmp(&0.0) != Some(std::cmp::Ordering::Greater);
    let crossed = children[..n].iter().zip(bounds).filter(|&(_, b)| kept(b)).map(|(&child, _)| child);
    let mut evaluations = n as u64;
    if size >= PARALLEL {
        let crossed: Vec<Node> = crossed.collect();
        let below: Vec<(Vec<[u64; 3]>, u64)> = crossed
            .into_par_iter()
            .map(|child| {
                let mut bricks = Vec::new();
                let spent = split(field, lattice, cells, child, half, &mut bricks);
                (bricks, spent)
            })
            .collect();
        for (bricks, spent) in below {
            found.extend(bricks);
            evaluations += spent;
        }
    } else {
        for child in crossed {
            evaluations += split(field, lattice, cells, child, half, found);
        }
    }
    evaluations
}
