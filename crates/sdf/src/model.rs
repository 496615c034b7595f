//! The sdf artifact: the terrain, the domain and the cave primitives.

use serde::{Deserialize, Serialize};

use karst_artifact::{Kind, Payload};
use karst_geology::Domain;

use crate::Capsule;
use crate::terrain::TerrainField;

/// What the field is made of.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct SdfModel {
    pub domain: Domain,
    pub terrain: TerrainField,
    /// The conduits, as capsules along their segments.
    pub capsules: Vec<Capsule>,
}

impl Payload for SdfModel {
    const KIND: Kind = Kind::Sdf;
    const SCHEMA: u32 = 1;
}
