//! The output budget of a run: before the mesher runs, its work is estimated from sdf.bin and
//! the scene's cells ([`karst_mesher::Work`]: surface cells, triangles, bytes of the meshes) and
//! printed; beyond the budget (`karstgen run --budget MB`, default [`DEFAULT_MESH_MB`]) the run
//! stops with exit code 2, the estimate and the fields and flag that lower or raise it, before
//! a cell is evaluated. Budgets are bytes, not seconds: a refusal does not depend on the
//! machine's speed. (The memory budget, `--max-memory`, is checked by each stage itself.)

use karst_artifact::{StageId, read_artifact};
use karst_mesher::{MesherView, Work};
use karst_scene::SceneView;
use karst_scene::budget::bytes;
use karst_sdf::SdfModel;
use karst_stage::{Job, StageError};

/// The default budget of the meshes, MB (MiB).
pub const DEFAULT_MESH_MB: f64 = 300.0;

/// Bytes the outputs of a run may take.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct OutputBudget {
    /// Bytes of the meshes (mesh.bin) before any simplification.
    pub mesh_bytes: f64,
}

impl Default for OutputBudget {
    fn default() -> Self {
        OutputBudget { mesh_bytes: DEFAULT_MESH_MB * MB }
    }
}

impl OutputBudget {
    /// A budget of `megabytes` MB (MiB) for the meshes; refused unless finite and > 0.
    pub fn megabytes(megabytes: f64) -> Result<OutputBudget, String> {
        if !(megabytes.is_finite() && megabytes > 0.0) {
            return Err(format!("--budget {megabytes}: a budget is a number of MB above 0"));
        }
        Ok(OutputBudget { mesh_bytes: megabytes * MB })
    }
}

const MB: f64 = (1u64 << 20) as f64;

/// The mesher's work on the scene of `job` and the sdf.bin of its folder, as the line printed
/// before the mesher runs; a bad-input error (exit 2) when it is beyond `budget`.
pub fn check_mesher(job: &Job, budget: OutputBudget) -> Result<String, StageError> {
    let (_, model) = read_artifact::<SdfModel>(&job.artifact(StageId::Sdf))?;
    let view = MesherView::of(job.scene);
    let work = Work::of(&view, &model);
    let estimate = format!(
        "about {:.2e} surface cells, {:.2e} triangles, {} of meshes at mesher.cell_size = {} m",
        work.cells,
        work.triangles,
        bytes(work.bytes),
        view.mesher.cell_size
    );
    if work.bytes > budget.mesh_bytes {
        return Err(StageError::scene(format!(
            "{}: the mesher would make {estimate}, more than the budget of {}: raise mesher.cell_size \
             or mesher.cave_cell_size (the bytes grow as 1 / cell²) to lower it, or run with --budget MB \
             to allow it",
            job.scene_path.display(),
            bytes(budget.mesh_bytes)
        )));
    }
    Ok(format!("{:<10} estimate    {estimate} (budget {})", "mesher", bytes(budget.mesh_bytes)))
}
