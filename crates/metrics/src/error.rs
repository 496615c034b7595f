//! Why the metrics stage cannot report on a network.

use karst_artifact::StageId;
use karst_stage::{Blame, Failure};

use crate::MetricsError;

/// A report that cannot be made.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum ReportError {
    /// The skeleton's network cannot be characterised.
    #[error("{0}")]
    Network(MetricsError),
    #[error("describes {hydro} conduits, skeleton.json has {skeleton}")]
    ConduitCounts { hydro: usize, skeleton: usize },
    #[error("conduit {conduit} has {segments} water segments, which does not match skeleton.json")]
    Segments { conduit: usize, segments: usize },
    /// The scene's calibration target cannot be resolved.
    #[error("calibrate.{field} = \"{value}\": {message}")]
    Aim { field: &'static str, value: String, message: String },
}

impl Failure for ReportError {
    fn blame(&self) -> Blame {
        match self {
            ReportError::Network(_) => Blame::Artifact(StageId::Skeleton),
            ReportError::Aim { .. } => Blame::Scene,
            ReportError::ConduitCounts { .. } | ReportError::Segments { .. } => {
                Blame::Artifact(StageId::Hydro)
            }
        }
    }
}
