//! Stage 2: the cost graph, the discrete medium in which conduits are least-cost paths.
//!
//! Every sample is joined to its k nearest neighbours (directed edges, built in parallel with a
//! k-d tree); each edge carries a cost: its length times the mean cost per metre of the rock it
//! crosses, integrated along the whole edge (Simpson's rule), never at one endpoint only. The
//! cost per metre is ≥ 1, so every edge costs at least its length and no cost is ever zero.
//! Output: `costgraph.bin` ([`CostGraph`], compressed sparse rows).

pub mod cost;
pub mod graph;
pub mod knn;
pub mod stage;

pub use cost::CostModel;
pub use graph::CostGraph;
