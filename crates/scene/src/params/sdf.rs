//! `[sdf]`: the signed-distance model (docs/sdf.md).

use serde::{Deserialize, Serialize};

use crate::validate::Checks;

#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct SdfParams {
    /// Factor applied to every conduit radius.
    pub radius_scale: f64,
    /// Height over width of the sections, as a factor on each type's own proportions.
    pub ratio: f64,
    /// Sideways shear of the sections' upper half, in half-widths (meander undercuts); each
    /// conduit leans to a random side.
    pub asymmetry: f64,
    /// Conduits whose tortuosity 1 − chord/length exceeds this become unions of spheres
    /// (without passage profiles, `passage_detail = "off"`; with them every conduit is swept).
    pub tortuosity: f64,
    /// Spacing of the spheres of tortuous conduits, in conduit radii (`passage_detail = "off"`).
    pub sphere_spacing: f64,
    /// Radius of the smooth union where conduits open to the surface, metres.
    pub blend: f64,
    /// Amplitude of the wall detail noise, metres (times a per-type factor).
    pub detail: f64,
    /// Base wavelength of the detail noise, metres.
    pub detail_wavelength: f64,
    /// Chamber foundation radius, in conduit radii.
    pub chamber_scale: f64,
    /// Cui et al.'s bias b of the chamber walls, in (0, 0.5]: small hugs the foundation.
    pub chamber_bias: f64,
    /// How much passage detail the cave gets (docs/sdf.md): `full` (the default) and `passages`
    /// vary the cross-sections along each conduit as surveyed passages do, `full` adding rough
    /// walls, speleothems, breakdown and sediment floors; `off` keeps every conduit's size and
    /// shape as the radius process gives them (the artifacts of karstgen before passage detail).
    pub passage_detail: PassageDetail,
    /// `full` only: amplitude of the rough-wall relief, as a fraction of the local passage
    /// radius (docs/sdf.md, "Rough walls").
    pub wall_relief: f64,
    /// `full` only: the largest wall-relief amplitude, metres.
    pub wall_relief_max: f64,
    /// `full` only: the longest wavelength of the wall relief, metres; its octaves halve it
    /// four times (a 4 m relief reaches 0.25 m).
    pub wall_wavelength: f64,
    /// `full` only: speleothems per metre of air-filled passage where the roof is at the
    /// ground (drip density at zero overburden; docs/sdf.md, "Speleothems").
    pub speleothem_density: f64,
    /// `full` only: the overburden over which the drip density falls by a factor e, metres.
    pub drip_depth: f64,
    /// `full` only: the median length of a stalactite or stalagmite, metres.
    pub speleothem_length: f64,
    /// `full` only: junctions whose largest passage radius is at least this many metres
    /// collapse into breakdown chambers (docs/sdf.md, "Breakdown").
    pub breakdown_radius: f64,
    /// `full` only: blocks on the floor of each breakdown chamber.
    pub breakdown_blocks: u32,
}

/// The `[sdf]` fields that only `passage_detail = "full"` reads: left out of the stage's key
/// at the other levels, whose artifacts they do not change.
pub const FULL_DETAIL_FIELDS: [&str; 8] = [
    "wall_relief",
    "wall_relief_max",
    "wall_wavelength",
    "speleothem_density",
    "drip_depth",
    "speleothem_length",
    "breakdown_radius",
    "breakdown_blocks",
];

/// Most blocks a breakdown chamber may hold.
pub const MAX_BREAKDOWN_BLOCKS: u32 = 200;

/// The level of passage detail, `[sdf] passage_detail`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum PassageDetail {
    /// The sizes of the radius process alone, constant shapes: the artifacts karstgen wrote
    /// before passage detail existed, byte for byte.
    Off,
    /// Cross-sections whose size and shape vary along each conduit (docs/skeleton.md).
    Passages,
    /// `passages` with rough walls, speleothems, breakdown and sediment floors (docs/sdf.md):
    /// the default.
    #[default]
    Full,
}

impl PassageDetail {
    /// Whether the cross-sections vary along the conduits.
    pub fn varies(self) -> bool {
        self != PassageDetail::Off
    }

    /// Whether the caves get rough walls, speleothems and breakdown.
    pub fn features(self) -> bool {
        self == PassageDetail::Full
    }

    /// The scene file's name of the level.
    pub fn name(self) -> &'static str {
        match self {
            PassageDetail::Off => "off",
            PassageDetail::Passages => "passages",
            PassageDetail::Full => "full",
        }
    }
}

impl Default for SdfParams {
    fn default() -> Self {
        SdfParams {
            radius_scale: 1.0,
            ratio: 1.0,
            asymmetry: 0.2,
            tortuosity: 0.15,
            sphere_spacing: 0.5,
            blend: 1.0,
            detail: 0.15,
            detail_wavelength: 3.0,
            chamber_scale: 2.0,
            chamber_bias: 0.2,
            passage_detail: PassageDetail::Full,
            wall_relief: 0.12,
            wall_relief_max: 0.5,
            wall_wavelength: 4.0,
            speleothem_density: 0.6,
            drip_depth: 40.0,
            speleothem_length: 0.8,
            breakdown_radius: 4.0,
            breakdown_blocks: 24,
        }
    }
}

impl SdfParams {
    pub(crate) fn check(&self, c: &mut Checks) {
        c.within("sdf.radius_scale", self.radius_scale, 1e-3, 1e3);
        c.within("sdf.ratio", self.ratio, 1e-2, 1e2);
        if c.finite("sdf.asymmetry", &[self.asymmetry]) && self.asymmetry.abs() > 1.0 {
            c.report("sdf.asymmetry", format!("must be within [−1, 1], got {}", self.asymmetry));
        }
        c.within("sdf.tortuosity", self.tortuosity, 0.0, 1.0);
        if c.finite("sdf.sphere_spacing", &[self.sphere_spacing])
            && !(self.sphere_spacing >= 0.1 && self.sphere_spacing <= 1.0)
        {
            c.report(
                "sdf.sphere_spacing",
                format!("must be within [0.1, 1] radii, got {}", self.sphere_spacing),
            );
        }
        c.within("sdf.blend", self.blend, 0.0, 1e3);
        c.within("sdf.detail", self.detail, 0.0, 1e3);
        c.within("sdf.detail_wavelength", self.detail_wavelength, 1e-3, 1e6);
        c.within("sdf.chamber_scale", self.chamber_scale, 1e-2, 1e2);
        if c.finite("sdf.chamber_bias", &[self.chamber_bias])
            && !(self.chamber_bias > 0.0 && self.chamber_bias <= 0.5)
        {
            c.report("sdf.chamber_bias", format!("must be within (0, 0.5], got {}", self.chamber_bias));
        }
        c.within("sdf.wall_relief", self.wall_relief, 0.0, 0.5);
        c.within("sdf.wall_relief_max", self.wall_relief_max, 0.0, 10.0);
        c.within("sdf.wall_wavelength", self.wall_wavelength, 0.1, 100.0);
        c.within("sdf.speleothem_density", self.speleothem_density, 0.0, 10.0);
        c.within("sdf.drip_depth", self.drip_depth, 0.1, 1e4);
        c.within("sdf.speleothem_length", self.speleothem_length, 0.05, 20.0);
        c.within("sdf.breakdown_radius", self.breakdown_radius, 0.1, 1e3);
        if self.breakdown_blocks > MAX_BREAKDOWN_BLOCKS {
            c.report(
                "sdf.breakdown_blocks",
                format!("must be at most {MAX_BREAKDOWN_BLOCKS}, got {}", self.breakdown_blocks),
            );
        }
    }
}
