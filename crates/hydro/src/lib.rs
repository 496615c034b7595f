//! Stage 4: underground hydrology, after the hydraulic graph of Emilien et al. 2015 (§4.2, §5).
//!
//! The skeleton's conduits become the links of a hydraulic graph ([`graph`]) whose sources are
//! the sinks and whose wells are the springs. Every link is oriented downstream ([`orient`]:
//! elevation in the vadose zone, distance to the spring in the phreatic zone, consistently on
//! loops); the sinks' recharge (their weights, or their catchment on the terrain, [`recharge`])
//! is propagated in dependency order with the paper's angle-weighted split and equal split at
//! pools ([`flow`]). Each wet vadose segment gets a slope–flow water type of Table 1
//! ([`water`]) and a water geometry ([`geometry`]): free-surface depth and width, or the
//! parabola of a free fall in a shaft; phreatic segments are sumps. Conduits can be sized from
//! their flow ([`sizing`]). Outputs: `hydro.json` ([`Hydro`], docs/hydro.md), the CSV tables
//! of [`export`], and the water-type picture of [`render`].

pub mod artifact;
pub mod error;
pub mod export;
pub mod flow;
pub mod geometry;
pub mod graph;
pub mod hydraulics;
pub mod orient;
pub mod recharge;
pub mod render;
pub mod sizing;
pub mod stage;
pub mod water;

pub use artifact::{ConduitWater, Hydro, NodeWater, Role, SegmentWater};
pub use error::HydroError;
pub use hydraulics::{Inputs, compute};
pub use water::WaterType;
