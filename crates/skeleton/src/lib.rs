//! Stage 3: the skeleton, i.e. the conduit network.
//!
//! This first version routes every sink to its spring along the least-cost path of the cost
//! graph (Dijkstra with predecessors; a path's cost is the cost at its target) and merges the
//! routes into one network: routes that reach the same sample share its node. The network is
//! cut into conduits (branches between junctions, ends and key points) and every conduit gets a
//! radius. Output: `skeleton.json` ([`Skeleton`]), plus karstnet's `network_nodes.dat` /
//! `network_links.dat` written by the stage.

pub mod dijkstra;
pub mod karstnet;
pub mod network;
pub mod routing;
pub mod stage;

pub use network::{Conduit, Node, Route, Skeleton, Zone};
