//! Why a survey cannot be made.

use karst_artifact::StageId;
use karst_stage::{Blame, Failure};

/// A survey that cannot be made.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum SurveyError {
    /// No station found an open passage near it: the model was not carved along this skeleton.
    #[error(
        "none of the {stations} stations finds an open passage within {search} m: sdf.bin was not made from this \
         skeleton (rerun the sdf stage)"
    )]
    NothingOpen { stations: usize, search: f64 },
}

impl Failure for SurveyError {
    fn blame(&self) -> Blame {
        match self {
            SurveyError::NothingOpen { .. } => Blame::Artifact(StageId::Sdf),
        }
    }
}
