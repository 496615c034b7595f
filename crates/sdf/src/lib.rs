//! Stage 5: the signed-distance model of the carved terrain.
//!
//! Convention: the field f is negative in rock and positive in air (above the ground, inside
//! the caves, outside the domain). This first version is the terrain (Paris et al. 2021,
//! appendix A: (z − h)/√(1 + λ²)) intersected with the domain box, minus a union of capsules
//! along the conduits: f = max(f_terrain, f_box, −min_i capsule_i). Each operand is
//! 1-Lipschitz, and max, min and negation keep the bound, so |f(p) − f(q)| ≤ |p − q|: the
//! mesher may skip any box whose centre is farther from the surface than its half diagonal.
//! Output: `sdf.bin` ([`SdfModel`]); the bounding-volume hierarchy is rebuilt when loaded.

pub mod build;
pub mod bvh;
pub mod capsule;
pub mod field;
pub mod model;
pub mod stage;
pub mod terrain;

pub use capsule::Capsule;
pub use field::CarvedTerrain;
pub use model::SdfModel;
pub use terrain::TerrainField;
