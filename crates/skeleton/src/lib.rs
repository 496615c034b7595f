//! Stage 3: the skeleton, i.e. the conduit network.
//!
//! Two published methods, chosen by `skeleton.mode`: Paris et al. 2021's γ-skeleton of the key
//! points (`gamma.rs`) and KarstNSim's vadose-then-phreatic routing of every sink with cohesion
//! (`karstnsim.rs`, its phreatic legs' A* bounds in `cohesion_bound.rs` and `spring_distance.rs`),
//! both on the least-cost paths of the cost graph (`search.rs`) between the
//! route ends (`ends.rs`). The paths are
//! merged into one network and cut into conduits (`assemble.rs`); every segment gets a tunnel
//! type (`classify.rs`), a radius ([`ConduitRadii`]) and, with passage detail, a profile of
//! the passage's size and shape along it (`passages.rs`). [`build`] is the algorithm's entry
//! (`build.rs`), [`SkeletonStage`] the stage. Output: `skeleton.json` ([`Skeleton`],
//! `payload.rs`), plus karstnet's `network_nodes.dat` / `network_links.dat`.

mod ahead;
mod amplify;
mod assemble;
mod build;
mod classify;
mod cohesion_bound;
pub mod defaults;
mod ends;
mod error;
mod gamma;
mod karstnet;
mod karstnsim;
mod meander;
#[cfg(test)]
mod modes_tests;
mod nodes;
mod passages;
mod payload;
mod planes;
mod radii;
mod render;
mod search;
mod spring_distance;
pub mod stage;
mod tortuosity;
mod view;

pub use build::{build, mode_paths};
pub use error::SkeletonError;
pub use payload::{Conduit, ConduitType, Node, ProfilePoint, RATIO_RANGE, Route, Skeleton, Zone};
pub use radii::ConduitRadii;
pub use stage::{RESOLVED_FILE, SkeletonStage, resolved_toml};
pub use view::SkeletonView;
