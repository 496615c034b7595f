//! `[mesher]`: polygonization.

use serde::{Deserialize, Serialize};

use crate::validate::Checks;

#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct MesherParams {
    /// Edge of the finest cell, metres.
    pub cell_size: f64,
    /// Simplify each surface to at most this many triangles (0: no simplification).
    pub target_triangles: u64,
    /// Edge of the cells of the cave alone and the water, metres; 0 (the default): the
    /// length-weighted median of the conduits' half-thicknesses, at most `cell_size`; thinner
    /// conduits are meshed one cave cell thick, so that none falls between lattice points.
    pub cave_cell_size: f64,
}

impl Default for MesherParams {
    fn default() -> Self {
        MesherParams { cell_size: 2.0, target_triangles: 0, cave_cell_size: 0.0 }
    }
}

/// Largest `target_triangles` (a mesh is indexed by u32).
pub const MAX_TRIANGLES: u64 = 1 << 31;

impl MesherParams {
    pub(crate) fn check(&self, c: &mut Checks) {
        c.positive("mesher.cell_size", self.cell_size);
        c.non_negative("mesher.cave_cell_size", self.cave_cell_size);
        if self.target_triangles > MAX_TRIANGLES {
            c.report(
                "mesher.target_triangles",
                format!("must be at most {MAX_TRIANGLES}, got {}", self.target_triangles),
            );
        }
    }
}
