//! The conduit-probability grid: cubic cells of `cell` metres over the scene's domain, x
//! fastest, then y, then z; and the cells a realization's conduits pass through.
//!
//! A conduit occupies the cells its segments' axes pass through, sampled every quarter cell,
//! whatever its radius. `probability/grid.json` places the grid for other programs (the
//! viewer): `{"min": [x, y, z], "cell": c, "dims": [nx, ny, nz], "realizations": n}`.

use serde::{Deserialize, Serialize};

use karst_scene::Scene;
use karst_skeleton::Skeleton;

use crate::options::OptionError;

/// Grids larger than this are refused (a `u32` count per cell).
const MAX_CELLS: usize = 50_000_000;

/// The probability grid over a scene's domain.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Grid {
    /// The corner of cell (0, 0, 0), metres.
    pub min: [f64; 3],
    /// Edge of a cell, metres.
    pub cell: f64,
    /// Cells along x, y and z.
    pub dims: [usize; 3],
}

impl Grid {
    /// The grid of `cell`-metre cells covering the scene's domain.
    pub fn new(scene: &Scene, cell: f64) -> Result<Self, OptionError> {
        if !(cell.is_finite() && cell > 0.0) {
            return Err(OptionError::new("--cell", cell, "must be a length > 0 m"));
        }
        let (min, max) = (scene.domain().min, scene.domain().max);
        let dims = [0, 1, 2].map(|a| ((max[a] - min[a]) / cell).ceil().max(1.0) as usize);
        if dims.iter().try_fold(1usize, |n, &d| n.checked_mul(d)).is_none_or(|n| n > MAX_CELLS) {
            return Err(OptionError::new(
                "--cell",
                cell,
                format!("makes a grid of {dims:?} cells; choose a larger cell"),
            ));
        }
        Ok(Self { min, cell, dims })
    }

    /// Number of cells.
    pub fn cell_count(&self) -> usize {
        self.dims.iter().product()
    }

    /// Cells in one horizontal layer.
    pub fn layer(&self) -> usize {
        self.dims[0] * self.dims[1]
    }

    /// Index of the cell holding `p`, if inside.
    fn index(&self, p: [f64; 3]) -> Option<u32> {
        let mut ijk = [0usize; 3];
        for a in 0..3 {
            let t = ((p[a] - self.min[a]) / self.cell).floor();
            if !(t >= 0.0 && t < self.dims[a] as f64) {
                return None;
            }
            ijk[a] = t as usize;
        }
        Some(((ijk[2] * self.dims[1] + ijk[1]) * self.dims[0] + ijk[0]) as u32)
    }

    /// Sorted, distinct cells crossed by the skeleton's conduits.
    pub fn cells_of(&self, skeleton: &Skeleton) -> Vec<u32> {
        let mut cells = Vec::new();
        for [a, b] in skeleton.links() {
            let (pa, pb) = (skeleton.nodes[a as usize].position, skeleton.nodes[b as usize].position);
            let length = (0..3).map(|i| (pb[i] - pa[i]).powi(2)).sum::<f64>().sqrt();
            let steps = (length / (self.cell / 4.0)).ceil().max(1.0) as usize;
            for s in 0..=steps {
                let t = s as f64 / steps as f64;
                cells.extend(self.index([0, 1, 2].map(|i| pa[i] + (pb[i] - pa[i]) * t)));
            }
        }
        cells.sort_unstable();
        cells.dedup();
        cells
    }

    /// True when every index is a cell of this grid (a record read back from disk).
    pub fn holds(&self, cells: &[u32]) -> bool {
        cells.iter().all(|&c| (c as usize) < self.cell_count())
    }

    /// Column (x, y) of a cell index.
    pub fn column(&self, index: u32) -> usize {
        index as usize % self.layer()
    }

    /// `probability/grid.json`'s document.
    pub fn placement(&self, realizations: usize) -> serde_json::Value {
        serde_json::json!({
            "min": self.min, "cell": self.cell, "dims": self.dims, "realizations": realizations,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use karst_skeleton::{Conduit, ConduitType, Node, Zone};

    #[test]
    fn a_segment_marks_every_cell_its_axis_crosses() {
        let grid = Grid { min: [0.0; 3], cell: 10.0, dims: [5, 4, 3] };
        let node = |x: f64, y: f64, z: f64| Node {
            position: [x, y, z],
            sample: 0,
            keypoint: None,
            zone: Zone::Vadose,
        };
        let skeleton = Skeleton {
            nodes: vec![node(1.0, 1.0, 1.0), node(39.0, 1.0, 1.0), node(39.0, 1.0, 25.0)],
            conduits: vec![Conduit {
                nodes: vec![0, 1, 2],
                radius: vec![1.0; 3],
                types: vec![ConduitType::Tube; 2],
                phase: 0,
                keypoints: vec![],
                profile: Vec::new(),
            }],
            routes: vec![],
            derived: Default::default(),
        };
        // x cells 0..=3 of row y 0 in layer 0, then up the x = 3 column to layer 2.
        assert_eq!(grid.cells_of(&skeleton), [0, 1, 2, 3, 23, 43]);
        assert_eq!(grid.column(43), 3);
        assert!(grid.holds(&[59]) && !grid.holds(&[60]));
    }
}
