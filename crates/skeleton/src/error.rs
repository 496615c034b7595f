//! Why a network cannot be built from a scene and its cost graph.

use karst_artifact::StageId;
use karst_stage::{Blame, Failure};

/// A network that cannot be built.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum SkeletonError {
    #[error(
        "sink \"{sink}\" cannot reach spring \"{spring}\" through the cost graph (raise costgraph.k or max_edge_length)"
    )]
    SinkCannotReachSpring { sink: String, spring: String },
    #[error(
        "key points \"{a}\" and \"{b}\" cannot reach each other through the cost graph (raise costgraph.k or \
         max_edge_length, or move them into the bedrock)"
    )]
    KeyPointsApart { a: String, b: String },
    #[error(
        "key point \"{name}\" cannot reach the network through the cost graph (raise costgraph.k or max_edge_length)"
    )]
    KeyPointOffNetwork { name: String },
    #[error("key point \"{name}\" is not in samples.bin (the scene changed since sampling)")]
    KeyPointNotSampled { name: String },
    #[error("the cost graph has {nodes} nodes but samples.bin has {samples} samples")]
    GraphOfOtherSamples { nodes: usize, samples: usize },
    #[error("the cost graph {0}")]
    Costing(#[from] karst_costgraph::CostingError),
}

impl Failure for SkeletonError {
    fn blame(&self) -> Blame {
        match self {
            SkeletonError::SinkCannotReachSpring { .. }
            | SkeletonError::KeyPointsApart { .. }
            | SkeletonError::KeyPointOffNetwork { .. } => Blame::Scene,
            SkeletonError::KeyPointNotSampled { .. } => Blame::Artifact(StageId::Sampling),
            SkeletonError::GraphOfOtherSamples { .. } | SkeletonError::Costing(_) => {
                Blame::Artifact(StageId::Costgraph)
            }
        }
    }
}
