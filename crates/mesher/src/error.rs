//! Why a model cannot be meshed.

use karst_stage::{Blame, Failure};

/// A mesh that cannot be built.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum MesherError {
    #[error(
        "{field} = {cell_size} gives {cells:.0} cells along the domain's longest axis; at most {max} are possible"
    )]
    LatticeTooFine { field: &'static str, cell_size: f64, cells: f64, max: f64 },
    #[error(
        "the {surface} mesh is empty: no surface of the model crosses the lattice of {field} = {cell_size} m \
         (a terrain steeper than the domain is tall, or conduits thinner than the cell?)"
    )]
    Empty { surface: &'static str, field: &'static str, cell_size: f64 },
    /// The streamed stage could not write its spill files or its artifact.
    #[error("cannot write the mesh: {0}")]
    Write(String),
    /// mesh.bin would pass the run's output budget (`karstgen run --budget`).
    #[error(
        "the mesher would make {estimate}, more than the budget of {budget}: raise mesher.cell_size \
         or mesher.cave_cell_size (the bytes grow as 1 / cell²) to lower it, or run with --budget MB \
         to allow it"
    )]
    OverOutput { estimate: String, budget: String },
    #[error(transparent)]
    OverBudget(#[from] karst_scene::budget::OverBudget),
}

impl Failure for MesherError {
    fn blame(&self) -> Blame {
        match self {
            MesherError::LatticeTooFine { .. }
            | MesherError::Empty { .. }
            | MesherError::OverOutput { .. }
            | MesherError::OverBudget(_) => Blame::Scene,
            MesherError::Write(_) => Blame::Internal,
        }
    }
}
