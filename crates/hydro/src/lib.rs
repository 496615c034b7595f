//! Stage 4: underground hydrology, after the hydraulic graph of Emilien et al. 2015 (§4.2, §5).
//!
//! The skeleton's conduits become the links of a hydraulic graph (`graph.rs`) whose sources are
//! the sinks and whose wells are the springs. Every link is oriented downstream (`orient.rs`:
//! elevation in the vadose zone, distance to the spring in the phreatic zone, consistently on
//! loops); the sinks' recharge (their weights, or their catchment on the terrain, `recharge.rs`)
//! is propagated in dependency order with the paper's angle-weighted split and equal split at
//! pools (`flow.rs`). Each wet vadose segment gets a slope–flow water type of Table 1
//! (`water.rs`) and a water geometry (`geometry.rs`): free-surface depth and width, or the
//! parabola of a free fall in a shaft; phreatic segments are sumps. Conduits can be sized from
//! their flow (`sizing.rs`). [`build`] (`build.rs`) is the entry,
//! [`HydroStage`] the stage. Outputs: `hydro.json` ([`Hydro`], `payload.rs`, docs/hydro.md),
//! the CSV tables of `export.rs`, and the water-type picture of `render.rs`.

mod build;
mod error;
pub mod export;
mod flow;
mod geometry;
mod graph;
mod hydraulics;
mod orient;
mod payload;
mod recharge;
mod render;
mod sizing;
pub mod stage;
mod view;
mod water;

pub use build::build;
pub use error::HydroError;
pub use flow::{Split, split};
pub use geometry::{FreeSurface, G};
pub use hydraulics::{Inputs, compute};
pub use payload::{ConduitWater, FlowUnits, Hydro, NodeWater, Role, SegmentWater, Sink, Spring};
pub use render::{colour, picture};
pub use stage::HydroStage;
pub use view::HydroView;
pub use water::{FlowScale, Look, WaterType, classify};
