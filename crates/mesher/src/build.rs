//! Meshing a model: the carved terrain and the cave alone, each polygonized and cleaned, and
//! the water in the conduits. [`build`] is the stage's entry: the cells from the scene, checked,
//! then [`mesh_simplified`].

use glam::DVec3;

use karst_scene::{KeyPoint, KeyPointKind};
use karst_sdf::{CarvedTerrain, SdfModel};

use std::io::Write;

use karst_artifact::check::{self, MAX_COORDINATE};
use karst_stage::ArtifactOut;

use crate::cell::{cave_cells, thickened};
use crate::cleanup::{Solid, clean};
use crate::error::MesherError;
use crate::estimate::{self, Work};
use crate::payload::{Mesh, SurfaceCounts};
use crate::polygonize::{polygonize, polygonize_into};
use crate::simplify::simplify;
use crate::spilled::{self, SpilledSurface};
use crate::terrain::{polygonize_terrain, polygonize_terrain_into};
use crate::view::MesherView;
use crate::volume::{Cave, Water};

/// The meshes of `model` under the scene's `[mesher]` cells, the sinks and springs kept open.
pub fn build(view: &MesherView, model: &SdfModel) -> Result<Mesh, MesherError> {
    let cave_cell = checked_cells(view, model)?;
    let params = view.mesher;
    let field = meshed_field(model, cave_cell);
    let mesh = mesh_simplified(
        &field,
        params.cell_size,
        cave_cell,
        &anchors(view.keypoints),
        params.target_triangles,
    );
    not_empty(
        mesh.cell_size,
        mesh.cave_cell_size,
        [mesh.terrain.triangles.len(), mesh.cave.triangles.len()],
    )?;
    Ok(mesh)
}

/// The field the mesher polygonizes: `model` with its conduits at least `cave_cell` thick on
/// each side ([`thickened`]), so that none falls between the cave lattice's points.
pub fn meshed_field(model: &SdfModel, cave_cell: f64) -> CarvedTerrain {
    CarvedTerrain::new(thickened(model, cave_cell).unwrap_or_else(|| model.clone()))
}

/// The cave cell of the scene's `[mesher]`, once both cells and the work they make are checked:
/// against the memory budget, and against the run's output budget when it has one (the
/// estimate line is then printed on stderr, as `karstgen run` shows it before the mesher runs).
fn checked_cells(view: &MesherView, model: &SdfModel) -> Result<f64, MesherError> {
    let params = view.mesher;
    check_lattice(model, "mesher.cell_size", params.cell_size)?;
    let cave_of = cave_cells(model, params.cave_cell_size);
    // One estimate for both budgets: the run's output, printed before any cell is evaluated,
    // and the memory peak.
    let (cave_cell, work) =
        Work::planned(model, params.cell_size, params.cave_cell_size, cave_of(params.cell_size));
    check_lattice(model, "mesher.cave_cell_size", cave_cell)?;
    if let Some(output) = view.output_budget {
        eprintln!("{}", estimate::held_to(output, &work, params.cell_size)?);
    }
    estimate::check(view.budget, &work, model, params.cell_size, &cave_of)?;
    Ok(cave_cell)
}

/// Degenerate results are errors: the water may be absent, the rock and the cave may not.
fn not_empty(cell_size: f64, cave_cell_size: f64, [terrain, cave]: [usize; 2]) -> Result<(), MesherError> {
    for (surface, field, cell_size, triangles) in [
        ("terrain", "mesher.cell_size", cell_size, terrain),
        ("cave", "mesher.cave_cell_size", cave_cell_size, cave),
    ] {
        if triangles == 0 {
            return Err(MesherError::Empty { surface, field, cell_size });
        }
    }
    Ok(())
}

/// [`build`] without holding the meshes: each surface is polygonized into spill files beside
/// `artifact` (removed after, also on error), cleaned from them, then copied into the artifact
/// (`spilled.rs`). Returns the counts of the headline. Only for a scene that does not simplify
/// (`mesher.target_triangles` = 0: the simplification needs the whole surface). The artifact
/// is byte-identical to the one [`build`]'s mesh makes.
pub fn write_streamed(
    view: &MesherView,
    model: &SdfModel,
    artifact: &mut ArtifactOut<'_, Mesh>,
) -> Result<[SurfaceCounts; 3], MesherError> {
    let cave_cell = checked_cells(view, model)?;
    let cell = view.mesher.cell_size;
    let field = meshed_field(model, cave_cell);
    let model = field.model();
    let anchors = anchors(view.keypoints);
    let failed = |e: std::io::Error| MesherError::Write(e.to_string());
    let dir = artifact.path().parent().map_or_else(|| std::path::PathBuf::from("."), |d| d.to_path_buf());
    let spilled = |volume: &(dyn Fn(&mut SpilledSurface) -> std::io::Result<u64> + Sync),
                   name,
                   clean: Option<(Solid, f64)>| {
        let mut surface = SpilledSurface::create(&dir, name, clean.is_some())?;
        surface.field_evaluations = volume(&mut surface)?;
        surface.finish()?;
        if let Some((solid, cell)) = clean {
            surface.clean(solid, model, &anchors, cell)?;
        }
        Ok::<_, std::io::Error>(surface)
    };
    // The three surfaces are independent (each spills to its own files): polygonized side by
    // side, one surface's serial steps (a slab's barrier, the cleanup) overlap the others' work.
    let (terrain, (cave, water)) = rayon::join(
        || spilled(&|s| polygonize_terrain_into(&field, cell, s), "terrain", Some((Solid::Rock, cell))),
        || {
            rayon::join(
                || {
                    spilled(
                        &|s| polygonize_into(&Cave(&field), cave_cell, s),
                        "cave",
                        Some((Solid::Cave, cave_cell)),
                    )
                },
                || spilled(&|s| polygonize_into(&Water(&field), cave_cell, s), "water", None),
            )
        },
    );
    let (terrain, cave, water) = (terrain.map_err(failed)?, cave.map_err(failed)?, water.map_err(failed)?);
    not_empty(cell, cave_cell, [terrain.triangles() as usize, cave.triangles() as usize])?;
    artifact
        .write(|w| {
            let mut w = std::io::BufWriter::with_capacity(1 << 16, w);
            for (field, size) in [("cell_size", cell), ("cave_cell_size", cave_cell)] {
                check::positive(|| field.into(), size, MAX_COORDINATE).map_err(spilled::invalid)?;
            }
            w.write_all(&cell.to_le_bytes())?;
            w.write_all(&cave_cell.to_le_bytes())?;
            terrain.encode(&mut w, "terrain")?;
            cave.encode(&mut w, "cave")?;
            water.encode(&mut w, "water")?;
            w.flush()
        })
        .map_err(|e| {
            let cause = std::error::Error::source(&e).map(|c| format!(": {c}")).unwrap_or_default();
            MesherError::Write(format!("{e}{cause}"))
        })?;
    Ok([&terrain, &cave, &water].map(|s| SurfaceCounts {
        triangles: s.triangles(),
        vertices: s.vertices(),
        field_evaluations: s.field_evaluations,
        removed: s.removed,
    }))
}

/// The sinks and springs among `keypoints`: the cleanup keeps the air around them even when
/// it is sealed in rock.
pub fn anchors(keypoints: &[KeyPoint]) -> Vec<DVec3> {
    keypoints
        .iter()
        .filter(|k| matches!(k.kind, KeyPointKind::Sink | KeyPointKind::Spring))
        .map(|k| k.point())
        .collect()
}

/// Cells per axis the lattice may have: lattice point ids are (k·ny + j)·nx + i in a u64.
const MAX_CELLS_PER_AXIS: f64 = (1u64 << 21) as f64;

/// Refuses a cell size that would overflow the lattice's point ids.
fn check_lattice(model: &SdfModel, field: &'static str, cell_size: f64) -> Result<(), MesherError> {
    let cells = (model.domain.size() / cell_size).max_element() + 2.0;
    if cells > MAX_CELLS_PER_AXIS {
        return Err(MesherError::LatticeTooFine { field, cell_size, cells, max: MAX_CELLS_PER_AXIS });
    }
    Ok(())
}

/// The three surfaces of `field`, all at `cell_size`; `anchors` (sinks and springs) keep the
/// air around them even when it is sealed in rock.
pub fn mesh(field: &CarvedTerrain, cell_size: f64, anchors: &[DVec3]) -> Mesh {
    mesh_with(field, cell_size, cell_size, anchors)
}

/// [`mesh`] with the cave alone and the water at `cave_cell_size`.
pub fn mesh_with(field: &CarvedTerrain, cell_size: f64, cave_cell_size: f64, anchors: &[DVec3]) -> Mesh {
    let mut terrain = polygonize_terrain(field, cell_size);
    clean(&mut terrain, Solid::Rock, field.model(), anchors, cell_size);
    let mut cave = polygonize(&Cave(field), cave_cell_size);
    clean(&mut cave, Solid::Cave, field.model(), anchors, cave_cell_size);
    let water = polygonize(&Water(field), cave_cell_size);
    Mesh { cell_size, cave_cell_size, terrain, cave, water }
}

/// [`mesh_with`], then each surface simplified to at most `target_triangles` (0: not
/// simplified).
pub fn mesh_simplified(
    field: &CarvedTerrain,
    cell_size: f64,
    cave_cell_size: f64,
    anchors: &[DVec3],
    target_triangles: u64,
) -> Mesh {
    let mut mesh = mesh_with(field, cell_size, cave_cell_size, anchors);
    if target_triangles > 0 {
        for surface in [&mut mesh.terrain, &mut mesh.cave, &mut mesh.water] {
            simplify(surface, target_triangles as usize);
        }
    }
    mesh
}
