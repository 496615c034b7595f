//! The scene: the file that says what karstgen is to build, and what each stage may read of it.
//!
//! A scene file (TOML, documented field by field in `docs/scene.md`) describes the domain box,
//! the terrain, the geology (water tables, inception horizons, faults, fracture families), the
//! key points (sinks, springs, waypoints), which sink drains to which spring, one section of
//! parameters per stage, and the seed. [`Scene::load`] parses it, reads the data files it names
//! (through `karst-geodata`, into the model types of `karst-geology`) and validates it,
//! reporting every problem at once with the file, line and field. Stages read the scene
//! through a view ([`view!`], [`SceneView`]) of the sections they need; the hash of those
//! sections ([`Scene::sections_hash`]) is part of their artifact's key. The work estimates the
//! stages check against the memory budget are [`budget`]; the seeded random streams [`rng`].
//!
//! Once loaded, every coordinate is local: relative to the domain's `min` corner
//! ([`Scene::origin`], see `localize.rs`), so that f32 geometry keeps its precision whatever the
//! magnitude of the file's coordinates.

pub mod budget;
pub mod defaults;
pub mod keypoint;
mod links;
mod load;
mod localize;
pub mod output_budget;
pub mod params;
pub mod point_table;
pub mod rng;
pub mod scene;
pub mod sections;
mod spans;
mod validate;
pub mod view;

pub use keypoint::{KeyPoint, KeyPointKind, keypoints_of};
pub use scene::{Connectivity, Link, Phase, Scene, SceneError};
pub use sections::Section;
pub use validate::Problem;
pub use view::SceneView;

/// The ranges every scene is checked against (docs/limits.md); the largest coordinate is the
/// readers' own, `karst_geodata::MAX_COORDINATE`.
pub mod limits {
    pub use crate::validate::{MAX_EXTENT, MAX_KEYPOINTS, MAX_LENGTH, MAX_TERRAIN_SLOPE, MAX_WEIGHT};
}
