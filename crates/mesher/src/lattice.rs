//! The sampling lattice: points origin + cell·(i, j, k).

use glam::DVec3;

/// A regular lattice of `dims` points per axis.
#[derive(Debug, Clone, Copy)]
pub struct Lattice {
    pub origin: DVec3,
    pub cell: f64,
    /// Points per axis.
    pub dims: [u64; 3],
}

impl Lattice {
    /// The lattice of `cell` covering [lo, hi] with one extra cell on every side.
    pub fn around(lo: DVec3, hi: DVec3, cell: f64) -> Self {
        let origin = lo - DVec3::splat(cell);
        let cells = ((hi - lo) / cell).ceil() + DVec3::splat(2.0);
        Lattice { origin, cell, dims: [cells.x as u64 + 1, cells.y as u64 + 1, cells.z as u64 + 1] }
    }

    /// Position of lattice point (i, j, k).
    pub fn point(&self, [i, j, k]: [u64; 3]) -> DVec3 {
        self.origin + DVec3::new(i as f64, j as f64, k as f64) * self.cell
    }
}
