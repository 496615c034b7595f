//! The output budget of a run: the mesher holds its own work estimate to it (the run sets it on
//! the scene, [`karst_scene::Scene::set_output_budget`]; [`karst_mesher::Work`]: surface cells,
//! triangles, bytes of the meshes, printed before it starts, the same estimate as its memory
//! check); before the export runs, the bytes of each of its formats are estimated from the
//! counts of the artifacts ([`karst_export::estimate`]) and printed, and held with mesh.bin's
//! size against the same budget. Beyond the budget (`karstgen run --budget MB`, default
//! [`DEFAULT_OUTPUT_MB`]) the run stops with exit code 2, the estimate and the fields and flag
//! that lower or raise it, before a cell is evaluated or a file written. Budgets are bytes, not seconds: a refusal does not depend on the
//! machine's speed. (The memory budget, `--max-memory`, is checked by each stage itself.)

use karst_artifact::{StageId, read_artifact};
use karst_export::ExportView;
use karst_export::estimate::{Counts, Estimate, raster_pixels};
use karst_mesher::Mesh;
use karst_sampling::Samples;
use karst_scene::SceneView;
use karst_scene::budget::bytes;
use karst_skeleton::Skeleton;
use karst_stage::{Job, StageError};
use karst_streams::Streams;

pub use karst_scene::output_budget::{DEFAULT_OUTPUT_MB, OutputBudget};

/// The export's work on the artifacts of `job`'s folder, as the line printed before the export
/// runs; a bad-input error (exit 2) when mesh.bin and the exports would pass `budget`.
pub fn check_export(job: &Job, budget: OutputBudget) -> Result<String, StageError> {
    let view = ExportView::of(job.scene);
    let params = view.export;
    let (_, skeleton) = read_artifact::<Skeleton>(&job.artifact(StageId::Skeleton))?;
    let (_, samples) = read_artifact::<Samples>(&job.artifact(StageId::Sampling))?;
    let (_, streams) = read_artifact::<Streams>(&job.artifact(StageId::Streams))?;
    let mesh_file = job.artifact(StageId::Mesher);
    let (_, mesh) = read_artifact::<Mesh>(&mesh_file)?;
    let counts = Counts::of(Some(&skeleton), Some(&samples), Some(&streams), Some(&mesh), &params.surfaces);
    let extent = [0, 1].map(|a| view.domain.max[a] - view.domain.min[a]);
    let pixels = raster_pixels(extent, params.raster_cell);
    let formats = karst_export::formats(params, view.frame);
    let mesh_bytes = std::fs::metadata(&mesh_file).map_or(0, |m| m.len()) as f64;
    let estimate = Estimate::of(&formats, &counts, params, pixels, mesh_bytes);
    if estimate.total() > budget.bytes {
        return Err(StageError::scene(format!(
            "{}: the export would write {estimate}, more than the budget of {}: drop formats from \
             export.formats or surfaces from export.surfaces, lower export.gltf_max_mb, raise \
             mesher.cell_size or mesher.cave_cell_size, or run with --budget MB to allow it",
            job.scene_path.display(),
            bytes(budget.bytes)
        )));
    }
    Ok(format!("{:<10} estimate    {estimate} (budget {})", "export", bytes(budget.bytes)))
}
