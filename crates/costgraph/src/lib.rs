//! Stage 2: the cost graph, the discrete medium in which conduits are least-cost paths
//! (Paris et al. 2021 §4, KarstNSim §1.2–1.3).
//!
//! Every sample is joined to its k nearest neighbours within the maximum edge length (directed
//! edges, found in parallel with a k-d tree; optionally symmetrised). Each edge carries a cost
//! per cost set: its length times the mean along the edge of the chosen model's cost per metre
//! ([`cost`]), never at one endpoint only, and never ≤ 0. [`build`] is the algorithm's entry, [`CostgraphStage`] the stage. Output: `costgraph.bin`
//! ([`CostGraph`] in `payload.rs`, compressed sparse rows, u32 targets and f32 costs), with the distributions
//! of every cost term for `karst-costgraph inspect`. docs/costgraph.md explains the models.

mod build;
mod checks;
mod cost;
mod costs;
mod error;
mod estimate;
mod falloff;
mod grid;
mod joints;
mod knn;
mod payload;
mod stage;
mod stats;
mod view;

pub use build::{build, build_points};
pub use cost::{CostModel, fracture_families};
pub use costs::{Costing, SHARED_ROW};
pub use error::CostGraphError;
pub use joints::{assumed as assumed_joints, lineament_azimuth};
pub use knn::{transpose, transpose_values};
pub use payload::{CostGraph, CostSet, CostingError};
pub use stage::CostgraphStage;
pub use stats::{Histogram, SetStats, Summary, TermStats};
pub use view::CostgraphView;
