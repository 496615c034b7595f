//! The sdf artifact: the construction tree in compact form. The operators are fixed by the
//! model's meaning (terrain ∩ domain − smooth-union(karst), water = ∪ water pieces ∩ karst), so
//! only the leaves and a few constants are stored; sections are stored as their shape
//! parameters and rebuilt when the model is loaded, spheres as four f32.

use serde::{Deserialize, Serialize};

use karst_artifact::{Payload, StageId};
use karst_geology::Domain;
use karst_skeleton::ConduitType;

use crate::Capsule;
use crate::chamber::ChamberSpec;
use crate::noise::WaveNoise;
use crate::surface_water::SurfacePieces;
use crate::sweep::SweepSpec;
use crate::terrain::TerrainField;

/// The spheres of one tortuous conduit, with their conduit type (for the detail amplitude).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct SphereGroup {
    pub kind: ConduitType,
    /// (x, y, z, radius).
    pub spheres: Vec<[f32; 4]>,
}

/// A sweep with its conduit type.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct TypedSweep {
    pub kind: ConduitType,
    pub sweep: SweepSpec,
}

/// The water of one segment: the part of its sweep below `level` (height above the axis along
/// the section's up direction); `None` when the segment is flooded (a sump).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct WaterSpec {
    pub sweep: SweepSpec,
    pub level: Option<f32>,
}

/// What the field is made of.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct SdfModel {
    pub domain: Domain,
    pub terrain: TerrainField,
    /// Plain capsules (hand-made models and tests).
    pub capsules: Vec<Capsule>,
    /// Straight conduit segments.
    pub sweeps: Vec<TypedSweep>,
    /// Tortuous conduits.
    pub spheres: Vec<SphereGroup>,
    pub chambers: Vec<ChamberSpec>,
    pub water: Vec<WaterSpec>,
    /// Radius of the smooth union at cave entrances and between conduits, metres.
    pub blend: f64,
    /// Detail amplitude scale, metres (times the per-type factor).
    pub detail: f64,
    pub detail_noise: WaveNoise,
    pub chamber_noise: WaveNoise,
    /// Cui et al.'s bias b of the chambers, in (0, 0.5].
    pub chamber_bias: f64,
    /// Riverbeds, plunge basins, overhangs and surface water from the streams stage
    /// ([`crate::surface_water`]); empty without streams.
    pub surface: SurfacePieces,
}

impl Payload for SdfModel {
    const STAGE: StageId = StageId::Sdf;
    const SCHEMA: u32 = 3;
}

impl SdfModel {
    /// A model with no caves: the terrain cut to the domain.
    pub fn new(domain: Domain, terrain: TerrainField) -> Self {
        SdfModel {
            domain,
            terrain,
            capsules: Vec::new(),
            sweeps: Vec::new(),
            spheres: Vec::new(),
            chambers: Vec::new(),
            water: Vec::new(),
            blend: 0.0,
            detail: 0.0,
            detail_noise: WaveNoise { wavelength: 1.0, waves: Vec::new() },
            chamber_noise: WaveNoise { wavelength: 1.0, waves: Vec::new() },
            chamber_bias: 0.5,
            surface: SurfacePieces::default(),
        }
    }

    /// Leaves by kind: (name, count), in a fixed order.
    pub fn primitive_counts(&self) -> [(&'static str, usize); 5] {
        [
            ("sweep", self.sweeps.len()),
            ("sphere", self.spheres.iter().map(|g| g.spheres.len()).sum()),
            ("chamber", self.chambers.len()),
            ("capsule", self.capsules.len()),
            ("water", self.water.len()),
        ]
    }
}

/// Relative detail amplitude of each conduit type: phreatic tubes and beds are smooth
/// (dissolution under water polishes), vadose canyons and shafts rough, breakdown the roughest.
pub fn detail_factor(kind: ConduitType) -> f64 {
    match kind {
        ConduitType::Tube => 0.4,
        ConduitType::Bed => 0.3,
        ConduitType::Keyhole => 0.7,
        ConduitType::Passage => 0.8,
        ConduitType::Canyon => 1.0,
        ConduitType::Epikarst => 1.2,
        ConduitType::Chamber => 1.0,
    }
}
