//! Stage 6: the signed-distance model of the carved terrain (Paris et al. 2021 §6).
//!
//! Convention: the field f is negative in rock and positive in air (above the ground, inside
//! the caves, outside the domain). The construction tree is the terrain (appendix A:
//! (z − h)/√(1 + λ²)) intersected with the domain box, minus the karst volume: a union of
//! sweeps of piecewise-quadratic cross-sections (`tree/`: `section.rs`, `sweep.rs`; appendices
//! B and C), unions of spheres along tortuous conduits and noise-biased chambers (`chamber.rs`;
//! Cui et al. 2011 §3.1), with per-type detail noise (`noise.rs`, `ops.rs`) and, on request,
//! passage detail (`detail/`). Every leaf and operator keeps the 1-Lipschitz bound, so
//! |f(p) − f(q)| ≤ |p − q|: the mesher may skip any box whose centre is farther from the surface
//! than its half diagonal (`field/`: the tree evaluated). A separate water model holds the water
//! inside the conduits and on the surface (`water/`). [`build`] is the entry, [`SdfStage`] the
//! stage. Output: `sdf.bin` ([`SdfModel`], `payload.rs`); sections and the bounding-volume
//! hierarchy are rebuilt when loaded. See docs/sdf.md.

mod build;
pub mod detail;
mod error;
mod estimate;
mod field;
mod key_map;
mod mitre;
mod payload;
mod slice;
pub mod stage;
pub mod synthetic;
#[cfg(test)]
mod testing;
mod tree;
mod view;
mod water;

pub use build::build;
pub use error::SdfError;
pub use field::carved::{CarvedTerrain, Near};
pub use key_map::{KeyHasher, KeyMap};
pub use payload::SdfModel;
pub use stage::SdfStage;
pub use tree::capsule::Capsule;
pub use tree::section::{Section, Shape};
pub use tree::sweep::SectionSpec;
pub use tree::terrain::TerrainField;
pub use view::SdfView;
pub use water::surface::{Bed, PoolWater, Sheet, SurfacePieces, add as add_streams};
