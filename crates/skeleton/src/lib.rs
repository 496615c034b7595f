//! Stage 3: the skeleton, i.e. the conduit network.
//!
//! Two published methods, chosen by `skeleton.mode`: Paris et al. 2021's γ-skeleton of the key
//! points ([`gamma`]) and KarstNSim's vadose-then-phreatic routing of every sink with cohesion
//! ([`karstnsim`]), both on the least-cost paths of the cost graph ([`search`]). The paths are
//! merged into one network and cut into conduits ([`assemble`]); every segment gets a tunnel
//! type ([`classify`]). Output: `skeleton.json` ([`Skeleton`]), plus karstnet's
//! `network_nodes.dat` / `network_links.dat` and the per-node `network_nodes.csv` written by the stage.

pub mod amplify;
pub mod assemble;
pub mod classify;
pub mod gamma;
pub mod karstnet;
pub mod karstnsim;
pub mod network;
pub mod radius;
pub mod render;
pub mod routing;
pub mod search;
pub mod stage;
pub mod tortuosity;

pub use classify::ConduitType;
pub use network::{Conduit, Node, Route, Skeleton, Zone};
