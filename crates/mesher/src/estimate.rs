//! The mesher's work estimate, made before any cell is evaluated: about 2 triangles per cell²
//! of the surface areas estimated here (measured: 1.9 for the tiny scene's terrain and 1.7 for
//! its cave, 2.0 and 1.9 for the default scene's), counted at 2.5, and a triangle costs about
//! 64 bytes at the peak (its share of the vertices, the bricks and the cleanup; measured in
//! BENCHMARKS.md, "mesher"). The surfaces: the carved terrain at `cell_size` (the ground, the domain's sides
//! and bottom, the cave walls) and the cave alone and its water at the cave cell.

use karst_geology::budget::{Budget, Cheaper, Estimate, OverBudget};
use karst_sdf::SdfModel;

/// Triangles per cell² of estimated surface.
const TRIANGLES_PER_CELL: f64 = 2.5;
/// Bytes per triangle at the peak.
const BYTES_PER_TRIANGLE: f64 = 64.0;
/// Terrain samples per axis for its area.
const SAMPLES: usize = 64;

/// Areas of the surfaces, m²: the carved terrain's outside (ground, sides, bottom) and the
/// cave's walls.
struct Areas {
    outside: f64,
    cave: f64,
}

impl Areas {
    fn of(model: &SdfModel) -> Areas {
        let d = &model.domain;
        let size = d.size();
        let (dx, dy) = (size.x / SAMPLES as f64, size.y / SAMPLES as f64);
        let ground = |i: usize, j: usize| {
            let h = model.terrain.height(d.min[0] + i as f64 * dx, d.min[1] + j as f64 * dy);
            h.clamp(d.min[2], d.max[2])
        };
        let mut top = 0.0;
        let mut sides = 0.0;
        for j in 0..SAMPLES {
            for i in 0..SAMPLES {
                let (h, hx, hy) = (ground(i, j), ground(i + 1, j), ground(i, j + 1));
                top += ((hx - h) / dx).hypot((hy - h) / dy).hypot(1.0) * dx * dy;
            }
            sides += (ground(0, j) + ground(SAMPLES, j) - 2.0 * d.min[2]) * dy;
            sides += (ground(j, 0) + ground(j, SAMPLES) - 2.0 * d.min[2]) * dx;
        }
        let tau = std::f64::consts::TAU;
        let sweeps: f64 = model
            .sweeps
            .iter()
            .map(|s| {
                let shape = s.sweep.start.shape;
                let length =
                    glam::Vec3::from_array(s.sweep.a).distance(glam::Vec3::from_array(s.sweep.b)) as f64;
                tau * (shape.radius * shape.ratio.max(1.0)) as f64 * length
            })
            .sum();
        let spheres: f64 =
            model.spheres.iter().flat_map(|g| &g.spheres).map(|s| tau * (s[3] as f64).powi(2)).sum();
        let chambers: f64 = model.chambers.iter().map(|c| 2.0 * tau * (c.radius as f64 * 1.5).powi(2)).sum();
        let capsules: f64 = model.capsules.iter().map(|c| 2.0 * tau * c.radius.powi(2)).sum();
        Areas { outside: top + sides + size.x * size.y, cave: sweeps + spheres + chambers + capsules }
    }

    /// Bytes of the three meshes at terrain cell `cell` and cave cell `cave`.
    fn bytes(&self, cell: f64, cave: f64) -> f64 {
        let terrain = (self.outside + self.cave) / (cell * cell);
        let cave_and_water = 2.0 * self.cave / (cave * cave);
        (terrain + cave_and_water) * TRIANGLES_PER_CELL * BYTES_PER_TRIANGLE
    }
}

/// Refuses lattices whose meshes would not fit in the memory budget, naming the cell that
/// drives the estimate; `cave_of` gives the cave cell of a terrain cell.
pub fn check(
    budget: Budget,
    model: &SdfModel,
    cell: f64,
    cave_of: impl Fn(f64) -> f64,
) -> Result<(), OverBudget> {
    let areas = Areas::of(model);
    let cave = cave_of(cell);
    let bytes = areas.bytes(cell, cave);
    let terrain_share = (areas.outside + areas.cave) / (cell * cell);
    let cave_share = 2.0 * areas.cave / (cave * cave);
    let triangles = format!("{:.2e} triangles", (terrain_share + cave_share) * TRIANGLES_PER_CELL);
    if terrain_share >= cave_share {
        let estimate = Estimate { what: triangles, bytes, field: "mesher.cell_size".into(), value: cell };
        budget.check(estimate, Cheaper::Larger, false, |c| areas.bytes(c, cave_of(c)))
    } else {
        let estimate =
            Estimate { what: triangles, bytes, field: "mesher.cave_cell_size".into(), value: cave };
        budget.check(estimate, Cheaper::Larger, false, |c| areas.bytes(cell, c))
    }
}
