//! Stage 5: the signed-distance model of the carved terrain (Paris et al. 2021 §6).
//!
//! Convention: the field f is negative in rock and positive in air (above the ground, inside
//! the caves, outside the domain). The construction tree is the terrain (appendix A:
//! (z − h)/√(1 + λ²)) intersected with the domain box, minus the karst volume: a union of
//! sweeps of piecewise-quadratic cross-sections ([`section`], [`sweep`]; appendices B and C),
//! unions of spheres along tortuous conduits and noise-biased chambers ([`chamber`]; Cui et al.
//! 2011 §3.1), with per-type detail noise ([`noise`], [`ops`]). Every leaf and operator keeps
//! the 1-Lipschitz bound, so |f(p) − f(q)| ≤ |p − q|: the mesher may skip any box whose centre
//! is farther from the surface than its half diagonal. A separate water model holds the water
//! inside the conduits ([`water`]). Output: `sdf.bin` ([`SdfModel`]); sections and the
//! bounding-volume hierarchy are rebuilt when loaded. See docs/sdf.md.

pub mod build;
pub mod bvh;
pub mod capsule;
pub mod chamber;
pub mod field;
pub mod model;
pub mod noise;
pub mod ops;
pub mod primitive;
pub mod section;
pub mod slice;
pub mod stage;
pub mod surface_water;
pub mod sweep;
pub mod synthetic;
pub mod terrain;
pub mod water;

#[cfg(test)]
mod testing;

pub use capsule::Capsule;
pub use field::{CarvedTerrain, Near};
pub use model::SdfModel;
pub use terrain::TerrainField;
