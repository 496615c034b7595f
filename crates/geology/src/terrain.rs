//! The terrain: the ground surface z = h(x, y) that bounds the bedrock from above.
//!
//! The SDF stage needs h's Lipschitz bound λ (its steepest slope) to build the 1-Lipschitz
//! terrain distance (z − h)/√(1 + λ²) of Paris et al. 2021, appendix A.

use serde::{Deserialize, Serialize};

/// An analytic terrain.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(tag = "kind", rename_all = "snake_case", deny_unknown_fields)]
pub enum Terrain {
    /// A plane through `elevation` at `origin`, rising by `gradient` = [dz/dx, dz/dy]; the
    /// default gradient [0, 0] is a flat terrain.
    Plane {
        /// Elevation at `origin`, metres.
        elevation: f64,
        /// The point `[x, y]` where the elevation is given; default `[0, 0]`.
        #[serde(default)]
        origin: [f64; 2],
        /// Slope along x and y (dimensionless, 0.05 = 5 %); default flat.
        #[serde(default)]
        gradient: [f64; 2],
    },
}

impl Terrain {
    /// Elevation of the ground at (x, y).
    pub fn height(&self, x: f64, y: f64) -> f64 {
        match self {
            Terrain::Plane { elevation, origin, gradient } => {
                elevation + gradient[0] * (x - origin[0]) + gradient[1] * (y - origin[1])
            }
        }
    }

    /// Lipschitz bound λ of the height function: |h(a) − h(b)| ≤ λ |a − b|.
    pub fn lipschitz(&self) -> f64 {
        match self {
            Terrain::Plane { gradient, .. } => gradient[0].hypot(gradient[1]),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn tilted_plane() {
        let t = Terrain::Plane { elevation: 100.0, origin: [10.0, 0.0], gradient: [0.03, -0.04] };
        assert!((t.height(110.0, 100.0) - (100.0 + 3.0 - 4.0)).abs() < 1e-12);
        assert!((t.lipschitz() - 0.05).abs() < 1e-15);
    }
}
