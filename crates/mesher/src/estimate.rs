//! The mesher's work estimate, made before any cell is evaluated: [`Work`] (surface cells,
//! triangles and the bytes of mesh.bin, held against the output budget of a run) and
//! [`check`] (the memory peak, held against the memory budget); both from one estimate per
//! run, and [`held_to`] holds the bytes to a run's output budget. About 2 triangles come per
//! cell² of the surface areas estimated here, counted at 2.5, and a triangle costs about 64
//! bytes at the peak (its share of the vertices, the bricks and the cleanup; measured in
//! BENCHMARKS.md, "mesher"). The surfaces: the carved terrain at `cell_size` (the ground, the
//! domain's sides and bottom, the cave walls), or counted cell by cell on its terrain lattice
//! when it has one ([`crate::terrain_lattice`]), the cave alone and its water at the cave cell.
//! The cave's tortuous conduits are overlapping spheres: their union's area is probed, not
//! summed ([`Spheres::union_area`]).

use karst_scene::budget::{Budget, Cheaper, Estimate, MB, OverBudget, bytes};
use karst_scene::output_budget::{DEFAULT_OUTPUT_MB, OutputBudget};
use karst_sdf::{CarvedTerrain, SdfModel};
use rayon::prelude::*;

use crate::error::MesherError;
use crate::spheres::Spheres;
use crate::terrain_lattice::{TerrainLattice, coarse_cell};

use crate::view::MesherView;

/// Triangles per cell² of estimated surface.
const TRIANGLES_PER_CELL: f64 = 2.5;
/// Bytes per triangle at the peak.
const BYTES_PER_TRIANGLE: f64 = 64.0;
/// Bytes of mesh.bin per triangle: half a vertex (three f32) and three u32 indices, a little
/// less once encoded (13.7 to 15.3 on the fixture scenes).
const MESH_BYTES_PER_TRIANGLE: f64 = 15.0;

/// The share of the default output budget the automatic cave cell leaves the meshes: the rest
/// is the exports' (the glb alone may take a third of it) and the network's artifacts (a 6 km
/// real-terrain scene's run folder: 124 MB of exports and 43 MB of network artifacts beside
/// mesh.bin, BENCHMARKS.md).
pub const MESH_SHARE: f64 = 1.0 / 3.0;
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
                let length =
                    glam::Vec3::from_array(s.sweep.a).distance(glam::Vec3::from_array(s.sweep.b)) as f64;
                (perimeter(s.sweep.start.shape) + perimeter(s.sweep.end.shape)) / 2.0 * length
            })
            .sum();
        let spheres: f64 = model.spheres.iter().map(|g| Spheres::of(&g.spheres).union_area()).sum();
        let chambers: f64 = model.chambers.iter().map(|c| 2.0 * tau * (c.radius as f64 * 1.5).powi(2)).sum();
        let capsules: f64 = model.capsules.iter().map(|c| 2.0 * tau * c.radius.powi(2)).sum();
        Areas { outside: top + sides + size.x * size.y, cave: sweeps + spheres + chambers + capsules }
    }

    /// Surface cells of the carved terrain at `cell`, and of the cave and of its water at
    /// `cave`: the water's surface is counted as half the cave's (14 to 63 % on the fixture
    /// scenes).
    fn cells(&self, cell: f64, cave: f64) -> [f64; 3] {
        let cave_alone = self.cave / (cave * cave);
        [(self.outside + self.cave) / (cell * cell), cave_alone, cave_alone / 2.0]
    }
}

/// A section's perimeter, metres: the ellipse of its half-width and half-height (Ramanujan's
/// approximation; a tube's circle exactly, a flat bed's or a tall canyon's ellipse rather than
/// the circle around it).
fn perimeter(shape: karst_sdf::Shape) -> f64 {
    let (a, b) = (shape.radius as f64, (shape.radius * shape.ratio) as f64);
    std::f64::consts::PI * (3.0 * (a + b) - ((3.0 * a + b) * (a + 3.0 * b)).sqrt())
}

/// The mesher's work on a model at its cells, estimated from the model's domain, terrain and
/// primitives: what a run prints before the mesher starts and holds against its output budget.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Work {
    /// Surface cells polygonized (terrain, cave, water).
    pub cells: f64,
    /// Triangles of the carved terrain, before any simplification.
    pub terrain_triangles: f64,
    /// Triangles of the three meshes, before any simplification.
    pub triangles: f64,
    /// Bytes of mesh.bin with those triangles.
    pub bytes: f64,
}

impl Work {
    /// The work of meshing `model` under `view`'s `[mesher]` cells (the cave cell derived from
    /// the conduits when not set, as the mesher does).
    pub fn of(view: &MesherView, model: &SdfModel) -> Work {
        let (cell, requested) = (view.mesher.cell_size, view.mesher.cave_cell_size);
        Work::planned(model, cell, requested, crate::cell::cave_cell(model, cell, requested)).1
    }

    /// The cave cell the mesher uses at terrain cell `cell` and its work, from `cave`, the cave
    /// cell of `requested` ([`crate::cell::cave_cell`]: `requested` when positive, else the
    /// passages'). The automatic cave cell is coarsened when the meshes would pass
    /// [`MESH_SHARE`] of the default output budget, so that a large scene's default run keeps
    /// room for its exports: the cave's and the water's bytes grow as the inverse square of
    /// their cell, and the conduits thinner than the coarser cell are still meshed a cell
    /// thick, never closed (issue 40: the defaults adapt to the scene's extent).
    pub fn planned(model: &SdfModel, cell: f64, requested: f64, cave: f64) -> (f64, Work) {
        let work = Work::at(model, cell, cave);
        let share = MESH_SHARE * DEFAULT_OUTPUT_MB * MB;
        if requested > 0.0 || work.bytes <= share || cave >= cell {
            return (cave, work);
        }
        let terrain = work.terrain_triangles * MESH_BYTES_PER_TRIANGLE;
        let room = (share - terrain).max(share / 4.0);
        let coarser = (cave * ((work.bytes - terrain) / room).sqrt()).min(cell);
        (coarser, work.with_coarser_cave(coarser / cave))
    }

    /// The same work with the cave and the water meshed at a cell `ratio` times coarser: their
    /// cells ([`Areas::cells`]) go as the inverse square of the cell, the terrain's stay.
    fn with_coarser_cave(self, ratio: f64) -> Work {
        let cave_triangles = self.triangles - self.terrain_triangles;
        let scaled = cave_triangles / (ratio * ratio);
        let triangles = self.terrain_triangles + scaled;
        Work {
            cells: self.cells - (cave_triangles - scaled) / TRIANGLES_PER_CELL,
            terrain_triangles: self.terrain_triangles,
            triangles,
            bytes: triangles * MESH_BYTES_PER_TRIANGLE,
        }
    }

    /// The work of meshing `model` at terrain cell `cell` and cave cell `cave`. On a terrain
    /// lattice ([`TerrainLattice`]) the carved terrain's cells are counted on it
    /// ([`lattice_cells`]); on the uniform lattice they come from its area.
    pub fn at(model: &SdfModel, cell: f64, cave: f64) -> Work {
        let areas = Areas::of(model);
        let [terrain, cave_alone, water] = areas.cells(cell, cave);
        let lattice = (coarse_cell(model, cell) >= 2.0 * cell)
            .then(|| TerrainLattice::of(&CarvedTerrain::new(model.clone()), cell))
            .flatten();
        let (terrain_cells, terrain_triangles) = match lattice {
            Some(lattice) => {
                let cells = lattice_cells(&lattice, model);
                (cells, cells * LATTICE_TRIANGLES_PER_CELL)
            }
            None => (terrain, terrain * TRIANGLES_PER_CELL),
        };
        let cells = terrain_cells + cave_alone + water;
        let triangles = terrain_triangles + (cave_alone + water) * TRIANGLES_PER_CELL;
        Work { cells, terrain_triangles, triangles, bytes: triangles * MESH_BYTES_PER_TRIANGLE }
    }
}

/// Triangles per crossed cell of the terrain lattice: a heightfield crosses most cells as one
/// quadrilateral.
const LATTICE_TRIANGLES_PER_CELL: f64 = 2.0;

/// The cells of the terrain lattice that the carved terrain crosses, counted column by column:
/// in each column of the ground the z cells between the lowest and the highest of its corners'
/// heights (at least one), the cells of the domain's sides under the ground and of its floor;
/// over each fine patch, its own lattice's columns instead of the coarse ones. The caves'
/// walls inside the rock are not counted: away from the patches and the fine windows the
/// coarse cells do not resolve them (their pockets are filled by the cleanup).
fn lattice_cells(lattice: &TerrainLattice, model: &SdfModel) -> f64 {
    let [xs, ys, zs] = &lattice.planes;
    let (floor, ceiling) = (model.domain.min[2], model.domain.max[2]);
    let ground = |i: usize, j: usize| model.terrain.height(xs[i], ys[j]).clamp(floor, ceiling);
    // z planes below height h.
    let below = |h: f64| zs.partition_point(|&z| z < h) as f64;
    let (nx, ny) = (xs.len() - 1, ys.len() - 1);
    let patches: f64 = lattice
        .patches
        .iter()
        .map(|p| {
            let [pxs, pys, pzs] = &p.lattice.planes;
            ground_cells(model, pxs, pys, pzs)
                - ground_cells(model, &xs[p.lo[0]..=p.hi[0]], &ys[p.lo[1]..=p.hi[1]], zs)
        })
        .sum();
    let side = |heights: &mut dyn Iterator<Item = f64>| heights.map(|h| below(h) - below(floor)).sum::<f64>();
    let sides = side(&mut (0..nx).map(|i| ground(i, 0)))
        + side(&mut (0..nx).map(|i| ground(i, ny)))
        + side(&mut (0..ny).map(|j| ground(0, j)))
        + side(&mut (0..ny).map(|j| ground(nx, j)));
    ground_cells(model, xs, ys, zs) + patches + sides + (nx * ny) as f64
}

/// The cells of the lattice of planes `xs`, `ys`, `zs` that the ground crosses: in each column
/// the z cells between the lowest and the highest of its corners' heights, at least one.
fn ground_cells(model: &SdfModel, xs: &[f64], ys: &[f64], zs: &[f64]) -> f64 {
    let (floor, ceiling) = (model.domain.min[2], model.domain.max[2]);
    let ground = |i: usize, j: usize| model.terrain.height(xs[i], ys[j]).clamp(floor, ceiling);
    let below = |h: f64| zs.partition_point(|&z| z < h) as f64;
    let (nx, ny) = (xs.len() - 1, ys.len() - 1);
    let rows: Vec<f64> = (0..ny)
        .into_par_iter()
        .map(|j| {
            (0..nx)
                .map(|i| {
                    let h = [ground(i, j), ground(i + 1, j), ground(i, j + 1), ground(i + 1, j + 1)];
                    let (lo, hi) =
                        h.iter().fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), &v| (a.min(v), b.max(v)));
                    (below(hi) - below(lo)).max(1.0)
                })
                .sum()
        })
        .collect();
    rows.iter().sum()
}

/// Refuses lattices whose meshes would not fit in the memory budget, naming the cell that
/// drives the estimate; `work` is [`Work::at`] `cell` and its cave cell (the carved terrain
/// counted on its terrain lattice when it has one), each triangle [`BYTES_PER_TRIANGLE`] at
/// the peak; `cave_of` gives the cave cell of a terrain cell, for the cell that would fit.
pub fn check(
    budget: Budget,
    work: &Work,
    model: &SdfModel,
    cell: f64,
    cave_of: impl Fn(f64) -> f64,
) -> Result<(), OverBudget> {
    let cave = cave_of(cell);
    let peak = |w: Work| w.triangles * BYTES_PER_TRIANGLE;
    let triangles = format!("{:.2e} triangles", work.triangles);
    // The terrain's cell is to blame when its triangles dominate, or when the automatic cave
    // cell is held at the terrain's (its clamp): then only a larger `cell_size` lowers both.
    let cave_follows_cell = cave_of(2.0 * cell) != cave;
    if cave_follows_cell || work.terrain_triangles >= work.triangles - work.terrain_triangles {
        let estimate =
            Estimate { what: triangles, bytes: peak(*work), field: "mesher.cell_size".into(), value: cell };
        budget.check(estimate, Cheaper::Larger, false, |c| peak(Work::at(model, c, cave_of(c))))
    } else {
        let estimate = Estimate {
            what: triangles,
            bytes: peak(*work),
            field: "mesher.cave_cell_size".into(),
            value: cave,
        };
        budget.check(estimate, Cheaper::Larger, false, |c| peak(Work::at(model, cell, c)))
    }
}

/// Holds `work` at terrain cell `cell` to a run's output budget: the line a run prints before
/// the mesher starts, or the refusal (with the estimate and what lowers or raises it) when
/// mesh.bin would pass the budget. Bytes, not seconds: a refusal does not depend on the
/// machine's speed.
pub fn held_to(budget: OutputBudget, work: &Work, cell: f64) -> Result<String, MesherError> {
    let estimate = format!(
        "about {:.2e} surface cells, {:.2e} triangles ({:.2e} of the terrain), {} of meshes at \
         mesher.cell_size = {cell} m",
        work.cells,
        work.triangles,
        work.terrain_triangles,
        bytes(work.bytes),
    );
    if work.bytes > budget.bytes {
        return Err(MesherError::OverOutput { estimate, budget: bytes(budget.bytes) });
    }
    Ok(format!("{:<10} estimate    {estimate} (budget {})", "mesher", bytes(budget.bytes)))
}

#[cfg(test)]
mod tests {
    use super::*;
    use karst_artifact::read_artifact;

    #[test]
    fn a_coarser_cave_is_derived_as_the_estimate_would_count_it() {
        let path = karst_testkit::fixture("fixtures/golden/tiny/sdf.bin");
        let (_, model) = read_artifact::<SdfModel>(&path).unwrap();
        let (cell, cave) = (3.0, 0.75);
        let derived = Work::at(&model, cell, cave).with_coarser_cave(2.0);
        let counted = Work::at(&model, cell, 2.0 * cave);
        let close = |a: f64, b: f64| (a - b).abs() <= 1e-9 * b.abs();
        assert!(close(derived.cells, counted.cells), "{derived:?} {counted:?}");
        assert!(close(derived.triangles, counted.triangles), "{derived:?} {counted:?}");
        assert!(close(derived.bytes, counted.bytes), "{derived:?} {counted:?}");
        assert_eq!(derived.terrain_triangles, counted.terrain_triangles);
    }
}
