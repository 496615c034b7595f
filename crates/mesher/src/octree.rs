//! Top-down octree over the lattice that keeps only the bricks the surface can cross.
//!
//! A node is a cube of lattice cells. When the field's bound over the node's box is positive
//! the surface cannot cross it and the whole subtree is skipped; otherwise it is split into
//! eight until the brick size is reached. The field is 1-Lipschitz, so skipping is exact.

use crate::lattice::Lattice;
use crate::volume::Volume;

/// Cells along a brick's edge.
pub const BRICK: u64 = 4;

/// Lattice cell coordinates of the first cell of every brick the surface may cross, in
/// (z, y, x) order, and the number of field evaluations spent finding them.
pub fn active_bricks<V: Volume>(field: &V, lattice: &Lattice) -> (Vec<[u64; 3]>, u64) {
    let cells = lattice.dims.map(|d| d - 1);
    let mut size = BRICK;
    while size < cells.into_iter().max().unwrap_or(0) {
        size *= 2;
    }
    let mut bricks = Vec::new();
    let mut evaluations = 0;
    visit(field, lattice, cells, [0; 3], size, &mut bricks, &mut evaluations);
    bricks.sort_unstable_by_key(|b| [b[2], b[1], b[0]]);
    (bricks, evaluations)
}

fn visit<V: Volume>(
    field: &V,
    lattice: &Lattice,
    cells: [u64; 3],
    at: [u64; 3],
    size: u64,
    bricks: &mut Vec<[u64; 3]>,
    evaluations: &mut u64,
) {
    if (0..3).any(|a| at[a] >= cells[a]) {
        return;
    }
    let end = [0, 1, 2].map(|a| (at[a] + size).min(cells[a]));
    let lo = lattice.point(at);
    let hi = lattice.point(end);
    *evaluations += 1;
    if field.bound(lo, hi) > 0.0 {
        return;
    }
    if size <= BRICK {
        bricks.push(at);
        return;
    }
    let half = size / 2;
    for dz in [0, half] {
        for dy in [0, half] {
            for dx in [0, half] {
                visit(field, lattice, cells, [at[0] + dx, at[1] + dy, at[2] + dz], half, bricks, evaluations);
            }
        }
    }
}
