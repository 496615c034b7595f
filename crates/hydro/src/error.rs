//! What can be wrong with the network handed to the hydro stage.

use karst_artifact::StageId;
use karst_stage::{Blame, Failure};
use thiserror::Error;

#[derive(Debug, Clone, PartialEq, Error)]
pub enum HydroError {
    #[error("the network has no spring: no route ends at a spring and no node is a spring key point")]
    NoSpring,
    #[error("sink \"{sink}\" (node {node}) has no downstream path: no conduit leads from it to a spring")]
    NoDownstreamPath { sink: String, node: u32 },
    #[error("hydro.pools[{index}]: no pool within {radius} m of {at:?} ({nearest})")]
    NoPoolNear { index: usize, at: [f64; 3], radius: f64, nearest: String },
    #[error("hydro.pools[{second}]: selects pool node {node}, which hydro.pools[{first}] already selects")]
    SamePool { first: usize, second: usize, node: u32 },
    #[error(
        "hydro.pools[{index}]: every outgoing conduit of pool node {node} gets weight 0: water could not leave it"
    )]
    PoolClosed { index: usize, node: u32 },
    #[error(transparent)]
    OverBudget(#[from] karst_scene::budget::OverBudget),
}

impl Failure for HydroError {
    /// The scene's `[hydro]` section is the scene's; the rest is about the network of
    /// skeleton.json (whose routes carry the sinks' weights).
    fn blame(&self) -> Blame {
        match self {
            HydroError::NoPoolNear { .. }
            | HydroError::SamePool { .. }
            | HydroError::PoolClosed { .. }
            | HydroError::OverBudget(_) => Blame::Scene,
            HydroError::NoSpring | HydroError::NoDownstreamPath { .. } => Blame::Artifact(StageId::Skeleton),
        }
    }
}
