//! Stage 3: the skeleton, i.e. the conduit network.
//!
//! This first version routes every sink to its spring along the least-cost path of the cost
//! graph (Dijkstra with predecessors; a path's cost is the cost at its target) and merges the
//! routes into one network: routes that reach the same sample share its node. The network is
//! cut into conduits (branches between junctions, ends and key points); every conduit gets a
//! radius and every segment a tunnel type ([`classify`]). Output: `skeleton.json` ([`Skeleton`]), plus karstnet's `network_nodes.dat` /
//! `network_links.dat` written by the stage.

pub mod classify;
pub mod dijkstra;
pub mod karstnet;
pub mod network;
pub mod routing;
pub mod stage;

pub use classify::ConduitType;
pub use network::{Conduit, Node, Route, Skeleton, Zone};
