//! The terrain leaf of the field: f_H(p) = (p_z − h(p_xy))/√(1 + λ²), 1-Lipschitz for a height
//! function h of Lipschitz bound λ (Paris et al. 2021, appendix A).
//!
//! The scene's terrain is copied into the artifact in this codec-friendly form (externally
//! tagged, so the binary codec can read it back), with its Lipschitz bound: planes and noise
//! by their parameters, heightfields by their whole grid of elevations.

use glam::DVec3;
use serde::{Deserialize, Serialize};

use karst_geology::Terrain;
use karst_geology::heightfield::HeightGrid;

/// The ground surface as the sdf artifact stores it.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub enum TerrainField {
    /// h(x, y) = elevation + g·(xy − origin).
    Plane { elevation: f64, origin: [f64; 2], gradient: [f64; 2] },
    /// A heightfield, bilinear (its grid carries its Lipschitz bound).
    Grid(HeightGrid),
    /// Value noise plus a slope (see `karst_geology::terrain`).
    Noise { elevation: f64, amplitude: f64, wavelength: f64, octaves: u32, gradient: [f64; 2] },
}

impl TerrainField {
    /// The field of the scene's terrain.
    pub fn of(terrain: &Terrain) -> Self {
        match terrain {
            Terrain::Plane { elevation, origin, gradient } => {
                TerrainField::Plane { elevation: *elevation, origin: *origin, gradient: *gradient }
            }
            Terrain::Heightfield { grid, .. } => TerrainField::Grid(HeightGrid::clone(grid)),
            // A loaded scene is local: its noise is anchored at [0, 0].
            Terrain::Noise { elevation, amplitude, wavelength, octaves, gradient, .. } => {
                TerrainField::Noise {
                    elevation: *elevation,
                    amplitude: *amplitude,
                    wavelength: *wavelength,
                    octaves: *octaves,
                    gradient: *gradient,
                }
            }
        }
    }

    /// Checks a decoded terrain: finite parameters, a grid of one height per node, a finite
    /// Lipschitz bound (the field divides by it).
    pub fn validate(&self) -> Result<(), karst_artifact::Invalid> {
        use karst_artifact::check::{self, MAX_COORDINATE, ensure};
        let finite = |name: &str, values: &[f64]| {
            ensure(
                values.iter().all(|v| v.is_finite()),
                || format!("terrain.{name}"),
                || format!("{values:?} is not finite"),
            )
        };
        match self {
            TerrainField::Plane { elevation, origin, gradient } => {
                finite("elevation", &[*elevation])?;
                finite("origin", origin)?;
                finite("gradient", gradient)?;
            }
            TerrainField::Noise { elevation, amplitude, wavelength, octaves, gradient } => {
                finite("elevation", &[*elevation, *amplitude])?;
                finite("gradient", gradient)?;
                check::positive(|| "terrain.wavelength".into(), *wavelength, MAX_COORDINATE)?;
                check::within(
                    || "terrain.octaves".into(),
                    *octaves as f64,
                    1.0,
                    karst_geology::terrain::MAX_OCTAVES as f64,
                )?;
            }
            TerrainField::Grid(grid) => {
                finite("origin", &grid.origin)?;
                check::positive(|| "terrain.cell_size".into(), grid.cell_size, MAX_COORDINATE)?;
                let nodes = (grid.nx as usize).checked_mul(grid.ny as usize).filter(|n| *n > 0);
                ensure(
                    nodes == Some(grid.heights.len()),
                    || "terrain.heights".into(),
                    || {
                        format!(
                            "holds {} heights for a grid of {} × {}",
                            grid.heights.len(),
                            grid.nx,
                            grid.ny
                        )
                    },
                )?;
                // The stored bound must hold: the field divides distances by it.
                let bound = grid.slope_bound();
                ensure(
                    grid.lipschitz >= bound,
                    || "terrain.lipschitz".into(),
                    || format!("{} is below the heights' steepest slope {bound}", grid.lipschitz),
                )?;
            }
        }
        check::within(|| "terrain".into(), self.lipschitz(), 0.0, f64::MAX).map_err(|e| {
            karst_artifact::Invalid::new(
                e.field,
                format!("its steepest slope {} is not finite", self.lipschitz()),
            )
        })
    }

    /// The analytic scene terrain this field stands for: the geology crate evaluates planes and
    /// noise, so their formulas live in one place. None for a grid.
    fn analytic(&self) -> Option<Terrain> {
        match *self {
            TerrainField::Plane { elevation, origin, gradient } => {
                Some(Terrain::Plane { elevation, origin, gradient })
            }
            TerrainField::Noise { elevation, amplitude, wavelength, octaves, gradient } => {
                Some(Terrain::Noise { elevation, amplitude, wavelength, octaves, gradient, anchor: [0.0; 2] })
            }
            TerrainField::Grid(_) => None,
        }
    }

    /// Ground elevation at (x, y).
    pub fn height(&self, x: f64, y: f64) -> f64 {
        match self {
            TerrainField::Grid(grid) => grid.height(x, y),
            _ => self.analytic().map_or(f64::NAN, |t| t.height(x, y)),
        }
    }

    /// Lipschitz bound λ of the height function.
    pub fn lipschitz(&self) -> f64 {
        match self {
            TerrainField::Grid(grid) => grid.lipschitz,
            _ => self.analytic().map_or(f64::NAN, |t| t.lipschitz()),
        }
    }

    /// 1/√(1 + λ²): the factor that makes z − h(x, y) a 1-Lipschitz distance bound.
    pub fn scale(&self) -> f64 {
        let lambda = self.lipschitz();
        1.0 / (1.0 + lambda * lambda).sqrt()
    }

    /// The 1-Lipschitz signed distance bound: positive above the ground.
    pub fn distance(&self, p: DVec3) -> f64 {
        (p.z - self.height(p.x, p.y)) * self.scale()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn agrees_with_the_scene_terrain() {
        let terrain = Terrain::Plane { elevation: 10.0, origin: [1.0, 2.0], gradient: [0.3, -0.4] };
        let field = TerrainField::of(&terrain);
        assert_eq!(field.height(7.0, -3.0), terrain.height(7.0, -3.0));
        assert_eq!(field.lipschitz(), terrain.lipschitz());
        assert!((field.distance(DVec3::new(1.0, 2.0, 15.0)) - 5.0 / 1.25f64.sqrt()).abs() < 1e-12);
        let noise = Terrain::Noise {
            elevation: 5.0,
            amplitude: 2.0,
            wavelength: 30.0,
            octaves: 2,
            gradient: [0.1, 0.0],
            anchor: [0.0; 2],
        };
        let field = TerrainField::of(&noise);
        assert_eq!(field.height(7.0, -3.0), noise.height(7.0, -3.0));
        assert_eq!(field.lipschitz(), noise.lipschitz());
    }

    #[test]
    fn heightfield_is_bilinear_with_its_bound() {
        let grid = HeightGrid::new([0.0, 0.0], 10.0, 2, 2, vec![1.0, 2.0, 3.0, 5.0]);
        let back = TerrainField::Grid(grid);
        assert!((back.height(5.0, 5.0) - 2.75).abs() < 1e-12);
        assert!((back.lipschitz() - 0.2f64.hypot(0.3)).abs() < 1e-12);
    }
}
