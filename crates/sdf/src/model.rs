//! The sdf artifact: the terrain, the domain and the cave primitives.

use serde::{Deserialize, Serialize};

use karst_artifact::{Kind, Payload};
use karst_geology::{Domain, Terrain};

use crate::Capsule;

/// What the field is made of.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct SdfModel {
    pub domain: Domain,
    pub terrain: Terrain,
    /// Lipschitz bound λ of the terrain's height function.
    pub terrain_lipschitz: f64,
    /// The conduits, as capsules along their segments.
    pub capsules: Vec<Capsule>,
}

impl Payload for SdfModel {
    const KIND: Kind = Kind::Sdf;
    const SCHEMA: u32 = 1;
}
