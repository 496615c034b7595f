//! The scene: everything karstgen knows about the ground before it starts.
//!
//! A scene file (TOML, documented field by field in `docs/scene.md`) describes the domain box,
//! the terrain, the geology (water tables, inception horizons, faults, fracture families), the
//! key points (sinks, springs,
//! waypoints), which sink drains to which spring, one section of parameters per stage, and the
//! seed. [`Scene::load`] parses and validates it, reporting every problem at once with the
//! file, line and field. Stages read the scene through this crate only; the hash of the
//! sections a stage reads ([`Scene::sections_hash`]) is part of its artifact's key.
//!
//! Conventions: metres, z up, right-handed; azimuths in degrees clockwise from north (+y).
//! Once loaded, every coordinate is local: relative to the domain's `min` corner
//! ([`Scene::origin`], see `localize.rs`), so that f32 geometry keeps its precision whatever the
//! magnitude of the file's coordinates.

pub mod budget;
pub mod crs;
mod csv;
pub mod defaults;
pub mod domain;
pub mod field;
pub mod fracture;
pub mod geokeys;
pub mod geotiff;
pub mod grids;
pub mod heightfield;
pub mod keypoint;
mod links;
pub mod lithology;
mod load;
mod localize;
mod npy;
pub mod params;
pub mod point_table;
pub mod rng;
pub mod scene;
pub mod sections;
mod spans;
pub mod surface;
pub mod terrain;
pub mod tin;
mod validate;
pub mod view;
mod vti;

pub use domain::Domain;
pub use fracture::FractureFamily;
pub use keypoint::{KeyPoint, KeyPointKind, keypoints_of};
pub use scene::{Connectivity, Geology, Link, Phase, Scene, SceneError};
pub use sections::Section;
pub use surface::{Geometry, Surface};
pub use terrain::Terrain;
pub use validate::Problem;
pub use view::SceneView;

/// The ranges every scene is checked against (docs/limits.md).
pub mod limits {
    pub use crate::validate::{
        MAX_COORDINATE, MAX_EXTENT, MAX_KEYPOINTS, MAX_LENGTH, MAX_TERRAIN_SLOPE, MAX_WEIGHT,
    };
}

/// A point in space, metres, z up.
pub type Point = glam::DVec3;
