//! The geological model: what karstgen knows about the ground before it starts.
//!
//! The domain box ([`Domain`]), the terrain ([`Terrain`]: a plane, noise or a heightfield,
//! [`heightfield`], [`grids`]), the geological surfaces (water tables, inception horizons,
//! faults: [`Surface`], planes or triangulated surfaces, [`tin`]), fracture families
//! ([`FractureFamily`]), and the karstification potential: layers of rock, a construction tree
//! of primitives, a background grid ([`field`]) and lithology voxels ([`lithology`]), gathered
//! in [`Geology`]. The files these come from are read by `karst-geodata`; the scene file that
//! names them, its validation and the stages' views of it are `karst-scene`.
//!
//! Conventions: metres, z up, right-handed; azimuths in degrees clockwise from north (+y).
//! Once a scene is loaded, every coordinate is local (relative to the domain's `min` corner).

pub mod domain;
pub mod field;
pub mod file_error;
pub mod fracture;
pub mod grids;
pub mod heightfield;
pub mod lithology;
pub mod model;
pub mod surface;
pub mod terrain;
pub mod tin;

pub use domain::Domain;
pub use fracture::FractureFamily;
pub use model::Geology;
pub use surface::{Geometry, Surface};
pub use terrain::Terrain;

/// A point in space, metres, z up.
pub type Point = glam::DVec3;
