//! Stage 5: the surface waterfall network (Emilien et al. 2015 §4–5): where the springs'
//! water runs on the terrain, and how.
//!
//! Water leaves every spring at its mouth (`mouth.rs`) and the user's controller curves
//! (`curves.rs`: contact, free-fall and pool controllers as Cardinal splines, lowered where
//! they climb, §4.1 and Fig. 5); it runs down the terrain by steepest descent with the minimum
//! slope, falls freely along a parabola from every lip the ground drops away from faster than
//! the water can follow, digs a plunge pool at the foot of each fall and fills hollows into
//! pools and lakes (`trace.rs`, `flood.rs`), until it leaves the domain. The hydraulic graph
//! (`network.rs`) carries the springs' discharge (hydro.json) and the terrain's catchment
//! (`catchment.rs`, on the grid of `ground.rs`), split at branches by w = 1 + u·v and equally
//! at pools (`flow.rs`, the hydro stage's rule); each segment gets its Table 1 type, speed,
//! width and depth (`water.rs`). [`build`] (`build.rs`) is the entry, [`StreamsStage`] the
//! stage. Output: `streams.json` ([`Streams`], `payload.rs`, docs/streams.md); [`map`]
//! (`render.rs`) draws it. The sdf stage carves the network into the terrain, the metrics
//! stage sums its lengths per type.

mod build;
mod catchment;
mod curves;
mod error;
mod flood;
mod flow;
mod ground;
mod mouth;
mod network;
mod payload;
mod render;
pub mod stage;
mod trace;
mod view;
mod water;

use glam::{DVec2, DVec3};

pub use build::build;
pub use curves::polygon_distance;
pub use error::StreamsError;
pub use payload::{Fall, Motion, Node, Outline, Pool, PoolKind, Role, Segment, SpringMouth, Streams};
pub use render::map;
pub use stage::StreamsStage;
pub use view::StreamsView;

/// Horizontal unit vector from `a` to `b` (x when they coincide).
pub fn heading(a: DVec3, b: DVec3) -> DVec2 {
    let d = (b - a).truncate();
    if d.length() > 1e-12 { d.normalize() } else { DVec2::X }
}
