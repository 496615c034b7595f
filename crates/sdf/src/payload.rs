//! The sdf artifact: the construction tree in compact form. The operators are fixed by the
//! model's meaning (terrain ∩ domain − smooth-union(karst), water = ∪ water pieces ∩ karst), so
//! only the leaves and a few constants are stored; sections are stored as their shape
//! parameters and rebuilt when the model is loaded, spheres as four f32.

use serde::{Deserialize, Serialize};

use karst_artifact::check::{self, MAX_COORDINATE, ensure};
use karst_artifact::{Invalid, Payload, StageId};
use karst_geology::Domain;
use karst_skeleton::ConduitType;

use crate::Capsule;
use crate::detail::FullDetail;
use crate::tree::chamber::ChamberSpec;
use crate::tree::noise::WaveNoise;
use crate::tree::sweep::{SectionChecks, SweepSpec, to_dvec};
use crate::tree::terrain::TerrainField;
use crate::water::surface::SurfacePieces;

/// The spheres of one tortuous conduit, with their conduit type (for the detail amplitude).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct SphereGroup {
    pub kind: ConduitType,
    /// (x, y, z, radius).
    pub spheres: Vec<[f32; 4]>,
}

/// A sweep with its conduit type. `continues`: the sweep is the next piece of the previous
/// sweep's straight segment (a passage profile's pieces), and the two are one leaf, capped at
/// the run's ends only ([`crate::tree::sweep::SweepTable::push_run`]).
///
/// In the artifact (postcard) the type and the flag are one byte, the type's index plus
/// [`CONTINUES`]: without profiles that is the byte the type alone was, so `passage_detail =
/// "off"` writes the artifact of karstgen before runs existed. Readable formats (`inspect
/// --json`) get the three fields.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TypedSweep {
    pub kind: ConduitType,
    pub continues: bool,
    pub sweep: SweepSpec,
}

/// The flag of a continuing sweep in the artifact's type byte.
const CONTINUES: u8 = 0x40;

#[derive(Serialize, Deserialize)]
struct ReadableSweep {
    kind: ConduitType,
    continues: bool,
    sweep: SweepSpec,
}

#[derive(Serialize, Deserialize)]
struct CompactSweep {
    tag: u8,
    sweep: SweepSpec,
}

impl Serialize for TypedSweep {
    fn serialize<S: serde::Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        let TypedSweep { kind, continues, sweep } = *self;
        if s.is_human_readable() {
            ReadableSweep { kind, continues, sweep }.serialize(s)
        } else {
            let tag = kind as u8 | if continues { CONTINUES } else { 0 };
            CompactSweep { tag, sweep }.serialize(s)
        }
    }
}

impl<'de> Deserialize<'de> for TypedSweep {
    fn deserialize<D: serde::Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        if d.is_human_readable() {
            let ReadableSweep { kind, continues, sweep } = ReadableSweep::deserialize(d)?;
            return Ok(TypedSweep { kind, continues, sweep });
        }
        let CompactSweep { tag, sweep } = CompactSweep::deserialize(d)?;
        let kind = ConduitType::ALL.get((tag & !CONTINUES) as usize).copied().ok_or_else(|| {
            serde::de::Error::custom(format!("sweep type byte {tag} names no conduit type"))
        })?;
        Ok(TypedSweep { kind, continues: tag & CONTINUES != 0, sweep })
    }
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
    /// ([`crate::water::surface`]); empty without streams.
    pub surface: SurfacePieces,
    /// Rough walls, speleothems and breakdown (`passage_detail = "full"`); no bytes at all
    /// when empty, so it must stay the last field ([`crate::detail`]).
    pub full: FullDetail,
}

impl Payload for SdfModel {
    const STAGE: StageId = StageId::Sdf;
    const SCHEMA: u32 = 3;

    /// A finite domain of positive extent, a terrain with a finite Lipschitz bound, finite
    /// leaves and surface-water pieces of positive size with sections that do not intersect
    /// themselves, and the noises the 1-Lipschitz bound assumes: what the mesher and the slices evaluate without checking.
    fn validate(&self) -> Result<(), Invalid> {
        check::position(|| "domain.min".into(), &self.domain.min)?;
        check::position(|| "domain.max".into(), &self.domain.max)?;
        ensure(
            (0..3).all(|a| self.domain.min[a] < self.domain.max[a]),
            || "domain".into(),
            || format!("{:?} – {:?} is not a box of positive extent", self.domain.min, self.domain.max),
        )?;
        self.terrain.validate()?;
        for (i, c) in self.capsules.iter().enumerate() {
            c.validate(&|| format!("capsules[{i}]"))?;
        }
        let mut sections = SectionChecks::default();
        for (i, s) in self.sweeps.iter().enumerate() {
            validate_sweep(&|| format!("sweeps[{i}].sweep"), &s.sweep, &mut sections)?;
        }
        let mut first = 0;
        for run in self.sweep_runs() {
            validate_run(first, run)?;
            first += run.len();
        }
        for (g, group) in self.spheres.iter().enumerate() {
            for (i, s) in group.spheres.iter().enumerate() {
                check::position_f32(|| format!("spheres[{g}].spheres[{i}]"), &s[..3])?;
                check::positive(|| format!("spheres[{g}].spheres[{i}].radius"), s[3] as f64, MAX_COORDINATE)?;
            }
        }
        for (i, c) in self.chambers.iter().enumerate() {
            check::position_f32(|| format!("chambers[{i}].a"), &c.a)?;
            check::position_f32(|| format!("chambers[{i}].b"), &c.b)?;
            check::positive(|| format!("chambers[{i}].radius"), c.radius as f64, MAX_COORDINATE)?;
        }
        for (i, w) in self.water.iter().enumerate() {
            validate_sweep(&|| format!("water[{i}].sweep"), &w.sweep, &mut sections)?;
            if let Some(level) = w.level {
                check::within(|| format!("water[{i}].level"), level as f64, -MAX_COORDINATE, MAX_COORDINATE)?;
            }
        }
        check::within(|| "blend".into(), self.blend, 0.0, MAX_COORDINATE)?;
        check::within(|| "detail".into(), self.detail, 0.0, MAX_COORDINATE)?;
        self.detail_noise.validate("detail_noise")?;
        self.chamber_noise.validate("chamber_noise")?;
        check::within(|| "chamber_bias".into(), self.chamber_bias, f64::MIN_POSITIVE, 0.5)?;
        self.surface.validate()?;
        self.full.validate()
    }
}

/// A sweep between two distinct finite points, with sections of finite positive size that do
/// not intersect themselves.
fn validate_sweep(
    at: &dyn Fn() -> String,
    sweep: &SweepSpec,
    sections: &mut SectionChecks,
) -> Result<(), Invalid> {
    check::position_f32(|| format!("{}.a", at()), &sweep.a)?;
    check::position_f32(|| format!("{}.b", at()), &sweep.b)?;
    ensure(sweep.a != sweep.b, at, || "starts where it ends: a sweep of length 0".into())?;
    for (end, spec) in [("start", &sweep.start), ("end", &sweep.end)] {
        let shape = &spec.shape;
        check::positive(|| format!("{}.{end}.shape.radius", at()), shape.radius as f64, MAX_COORDINATE)?;
        check::within(|| format!("{}.{end}.shape.ratio", at()), shape.ratio as f64, 1e-3, 1e3)?;
        check::within(|| format!("{}.{end}.shape.asymmetry", at()), shape.asymmetry as f64, -1.0, 1.0)?;
        sections.check(spec).map_err(|e| Invalid::new(format!("{}.{end}", at()), e.to_string()))?;
    }
    Ok(())
}

/// A run: its first sweep continues none, and each next one starts where the one before ends,
/// with its section and type, and its nodes lie along the run's axis in order (strictly
/// increasing abscissas, within a thousandth of the run's length of the axis), which the
/// run's leaf assumes.
fn validate_run(first: usize, run: &[TypedSweep]) -> Result<(), Invalid> {
    let at = |k: usize| move || format!("sweeps[{}].continues", first + k);
    ensure(!run[0].continues, at(0), || "the first sweep continues no sweep".into())?;
    for (k, w) in run.windows(2).enumerate() {
        let (p, q) = (&w[0], &w[1]);
        ensure(p.sweep.b == q.sweep.a && p.sweep.end == q.sweep.start, at(k + 1), || {
            "starts elsewhere, or with another section, than the previous sweep ends".into()
        })?;
        ensure(p.kind == q.kind, at(k + 1), || "has another conduit type than the previous sweep".into())?;
    }
    let (a, b) = (to_dvec(run[0].sweep.a), to_dvec(run[run.len() - 1].sweep.b));
    let (length, axis) = (a.distance(b), (b - a).normalize_or_zero());
    let mut previous = 0.0;
    for (k, s) in run.iter().enumerate().take(run.len() - 1) {
        let p = to_dvec(s.sweep.b) - a;
        let l = p.dot(axis);
        let off = (p - axis * l).length();
        ensure(l > previous && l < length && off <= 1e-3 * length, at(k + 1), || {
            format!("its start is not along the run's axis after the previous one ({l} m along, {off} m off)")
        })?;
        previous = l;
    }
    Ok(())
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
            full: FullDetail::default(),
        }
    }

    /// The sweeps by run: each a sweep and the sweeps that continue it.
    pub fn sweep_runs(&self) -> impl Iterator<Item = &[TypedSweep]> {
        self.sweeps.chunk_by(|_, next| next.continues)
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
