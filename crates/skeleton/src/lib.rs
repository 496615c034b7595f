//! Stage 3: the skeleton, i.e. the conduit network.
//!
//! Two published methods, chosen by `skeleton.mode` (`modes/`): Paris et al. 2021's γ-skeleton
//! of the key points (`gamma.rs`) and KarstNSim's vadose-then-phreatic routing of every sink
//! with cohesion (`karstnsim.rs`), both on the least-cost paths of the cost graph between the
//! route ends (`route/`: `search.rs`, `ends.rs`, the phreatic legs' A* bounds in
//! `cohesion_bound.rs` and `spring_distance.rs`). The paths are merged into one network and cut
//! into conduits (`network/`: `assemble.rs`); every segment gets a tunnel type (`classify.rs`),
//! a radius ([`ConduitRadii`]) and, with passage detail, a profile of the passage's size and
//! shape along it (`network/shape/`: `passages.rs`). [`build`] is the algorithm's entry
//! (`build.rs`), [`SkeletonStage`] the stage. Output: `skeleton.json` ([`Skeleton`],
//! `payload.rs`), plus karstnet's `network_nodes.dat` / `network_links.dat` (`output/`).

mod build;
pub mod defaults;
mod error;
mod modes;
mod network;
mod output;
mod payload;
mod route;
pub mod stage;
mod view;

pub use build::{build, mode_paths};
pub use error::SkeletonError;
pub use network::shape::radii::ConduitRadii;
pub use payload::{Conduit, ConduitType, Node, ProfilePoint, RATIO_RANGE, Route, Skeleton, Zone};
pub use stage::{RESOLVED_FILE, SkeletonStage, resolved_toml};
pub use view::SkeletonView;
