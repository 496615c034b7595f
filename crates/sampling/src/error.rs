//! What can go wrong when sampling a scene.

use karst_stage::{Blame, Failure};

/// A scene that cannot be sampled.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum SamplingError {
    /// No sample fits between the key points: the region is empty or thinner than the radius.
    #[error(
        "sampling.radius: no sample fits in the bedrock: the domain below the terrain and outside the \
         no-karst volumes is empty or thinner than the radius ({smallest} m at the smallest, \
         sampling.radius = {radius})"
    )]
    NothingToSample { smallest: f64, radius: f64 },
    /// The samples would not fit in the memory budget.
    #[error(transparent)]
    OverBudget(#[from] karst_scene::budget::OverBudget),
}

impl Failure for SamplingError {
    fn blame(&self) -> Blame {
        match self {
            SamplingError::NothingToSample { .. } | SamplingError::OverBudget(_) => Blame::Scene,
        }
    }
}
