//! Why a cost graph cannot be built from a scene and its samples.

use karst_stage::{Blame, Failure};

/// A cost graph that cannot be built; every case is bad input (exit 2).
#[derive(Debug, thiserror::Error)]
pub enum CostGraphError {
    #[error(
        "costgraph.k = {k} needs more than {k} samples, samples.bin has {samples}: lower costgraph.k or sampling.radius"
    )]
    TooFewSamples { k: usize, samples: usize },
    #[error(
        "key point \"{name}\" has no neighbour within costgraph.max_edge_length = {max_edge_length} m: raise max_edge_length or move the key point"
    )]
    IsolatedKeyPoint { name: String, max_edge_length: f64 },
    #[error(
        "sink \"{sink}\" cannot reach spring {springs} through the cost graph (costgraph.k = {k}, max_edge_length = {max_edge_length} m): raise k or max_edge_length, or set costgraph.symmetrise = true"
    )]
    Unreachable { sink: String, springs: String, k: usize, max_edge_length: f64 },
    #[error(
        "costgraph.cost_floor and the term weights (alpha_* or w_*) give an edge of {length} m the cost \
         {cost:e}, which a cost (32-bit float, finite and > 0) cannot hold: bring them within docs/limits.md's ranges"
    )]
    CostOutOfRange { cost: f64, length: f64 },
    #[error("tags[{index}] is {tag}, which the scene does not have ({count} in the scene)")]
    ForeignTag { index: usize, tag: String, count: usize },
    #[error(transparent)]
    OverBudget(#[from] karst_scene::budget::OverBudget),
}

impl Failure for CostGraphError {
    /// A tag the scene does not have comes from samples.bin (made from another scene, or
    /// damaged); every other case from the scene's parameters.
    fn blame(&self) -> Blame {
        match self {
            Self::ForeignTag { .. } => Blame::Artifact(karst_artifact::StageId::Sampling),
            _ => Blame::Scene,
        }
    }
}
