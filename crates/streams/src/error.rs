//! What can be wrong with the inputs of the streams stage: the scene's terrain, or a hydro.json
//! that does not belong to the scene.

use karst_artifact::StageId;
use karst_stage::{Blame, Failure};
use thiserror::Error;

#[derive(Debug, Clone, PartialEq, Error)]
pub enum StreamsError {
    #[error("names spring \"{0}\", which is not a spring of the scene")]
    UnknownSpring(String),
    #[error("spring \"{name}\" has flow {flow}: flows must be finite numbers ≥ 0")]
    BadFlow { name: String, flow: f64 },
    #[error("terrain: the height at [{x}, {y}] is {height}: the streams need a finite terrain")]
    Terrain { x: f64, y: f64, height: f64 },
    #[error("the surface network has a loop: an internal error of the streams stage")]
    Loop,
}

impl Failure for StreamsError {
    /// The terrain is the scene's; spring names and flows come from hydro.json; a loop is
    /// karstgen's own fault (tracing never makes one).
    fn blame(&self) -> Blame {
        match self {
            StreamsError::Terrain { .. } => Blame::Scene,
            StreamsError::UnknownSpring(_) | StreamsError::BadFlow { .. } => Blame::Artifact(StageId::Hydro),
            StreamsError::Loop => Blame::Internal,
        }
    }
}
