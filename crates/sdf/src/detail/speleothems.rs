//! Speleothems: stalactites, stalagmites, columns and flowstone in the air-filled passages.
//!
//! **Where water drips.** Calcite is deposited where seepage water that took up CO₂ in the soil
//! and dissolved limestone on its way down degasses in cave air (Ford & Williams 2007 ch. 8;
//! White 1988 ch. 9): only in air, so never in water-filled passages (sumps, pools, the
//! phreatic conduits under today's water table) and never on the floor of an active stream,
//! which carries the drips away and scours what would grow; decorated passages are mostly
//! relict, abandoned by their stream. Seepage is most abundant where the roof is close to the
//! epikarst and the soil: the drip density falls with the overburden o (the rock between the
//! roof and the ground) as exp(−o / `drip_depth`).
//!
//! **The rule.** Along every segment of the skeleton no steeper than 45°, a station every
//! metre carries a speleothem with probability `speleothem_density`·exp(−o/`drip_depth`)
//! (at most 1), o measured above the roof there. The station's point lies on the passage axis,
//! moved sideways by up to half the local half-width; the roof and the floor are found by
//! sphere tracing the carved walls (relief included) up and down from it. What grows is
//! drawn: a stalactite (45 %), a stalagmite (30 %; none over a stream), flowstone draped on
//! the nearer wall (15 %) or, where a stalactite and a stalagmite of the station's length
//! would meet, a column (10 %; none over a stream). Lengths are `speleothem_length` times a
//! log-normal factor (σ = 0.5), at most 70 % of the passage height. Water segments follow
//! crate::water::conduits::level; a station whose point is in water is skipped, one with water on the
//! floor below it grows nothing from the floor, and a piece whose middle or far end would be
//! in water is dropped.
//!
//! **The shapes** are round cones ([`super::rock::round_cone`], exact signed distances): a
//! stalactite's base ball sits in the roof and it tapers to a 2 cm tip; a stalagmite is
//! broader and blunt; a column is slightly wider at its foot; flowstone is a cone lying on the
//! wall, widening downwards, its balls centred on the wall so that half of it bulges out.

use glam::DVec3;
use karst_hydro::Hydro;
use karst_scene::params::SdfParams;
use karst_scene::rng::Random;
use karst_skeleton::Skeleton;

use super::rock::{Piece, PieceKind, Shape};
use crate::field::carved::CarvedTerrain;
use crate::water::conduits::{self, Water};

/// Steepest segment that carries speleothems (rise over run): 45°.
const MAX_SLOPE: f64 = 1.0;
/// Spacing of the stations, metres.
const STATION: f64 = 1.0;
/// Lowest passage, metres, that carries speleothems.
const MIN_HEIGHT: f64 = 0.6;
/// Radius of a stalactite's tip, metres.
const TIP: f64 = 0.02;

/// Where a station's speleothem grows: its point in the air, roof and floor heights.
struct Station {
    at: DVec3,
    roof: f64,
    floor: f64,
    stream: bool,
}

/// The speleothems of the network, drawn from `random`.
pub fn place(
    field: &CarvedTerrain,
    skeleton: &Skeleton,
    hydro: &Hydro,
    p: &SdfParams,
    random: &mut Random,
) -> Vec<Piece> {
    let mut out = Vec::new();
    for (c, conduit) in skeleton.conduits.iter().enumerate() {
        for (i, w) in conduit.nodes.windows(2).enumerate() {
            let (a, b) = (w[0] as usize, w[1] as usize);
            let (pa, pb) = (
                DVec3::from_array(skeleton.nodes[a].position),
                DVec3::from_array(skeleton.nodes[b].position),
            );
            let Some(wet) = hydro.conduits.get(c).and_then(|h| h.segments.get(i)) else { continue };
            let radius = conduit.radius[i].max(conduit.radius[i + 1]) * p.radius_scale;
            let segment = conduits::Segment {
                kind: conduit.types[i],
                zones: [skeleton.nodes[a].zone, skeleton.nodes[b].zone],
                water: wet.water,
                depth: wet.depth,
                height: 2.0 * radius,
            };
            let stream = match conduits::level(&segment) {
                Water::Flooded => continue,
                Water::Stream { .. } => true,
                Water::None => false,
            };
            let run = (pb - pa).truncate().length();
            if (pb.z - pa.z).abs() > MAX_SLOPE * run {
                continue;
            }
            let length = pa.distance(pb);
            let side = DVec3::new(pa.y - pb.y, pb.x - pa.x, 0.0).normalize_or_zero();
            let stations = (length / STATION).floor() as usize;
            for k in 0..stations {
                let t = (k as f64 + random.uniform()) * STATION / length;
                let shift = random.range(-0.5, 0.5) * radius;
                let u = random.uniform();
                let Some(found) = station(field, pa.lerp(pb, t) + side * shift, stream) else { continue };
                let overburden = field.model().terrain.height(found.at.x, found.at.y) - found.roof;
                if overburden < 0.0
                    || u >= p.speleothem_density * STATION * (-overburden / p.drip_depth).exp()
                {
                    continue;
                }
                out.extend(grow(field, &found, p, random).filter(|piece| dry(field, piece)));
            }
        }
    }
    out
}

/// The station at `at` when it lies in dry air with a roof and a floor above and below.
fn station(field: &CarvedTerrain, at: DVec3, stream: bool) -> Option<Station> {
    if field.cave(at) > -0.1 || field.water(at) < 0.0 {
        return None;
    }
    let roof = at.z + trace(field, at, DVec3::Z, 30.0)?;
    let floor = at.z - trace(field, at, -DVec3::Z, 30.0)?;
    // Water on the floor below (a stream of this segment or of a passage beneath): no foot.
    let wet_floor = field.water(DVec3::new(at.x, at.y, floor + 0.05)) < 0.0;
    (roof - floor >= MIN_HEIGHT).then_some(Station { at, roof, floor, stream: stream || wet_floor })
}

/// Whether the piece stays out of the water: its axis's middle and its second ball's centre
/// (a stalactite's tip, a stalagmite's top) are dry.
fn dry(field: &CarvedTerrain, piece: &Piece) -> bool {
    let Shape::Cone { a, b, .. } = piece.shape else { return true };
    let (a, b) = (a.map(|c| c as f64), b.map(|c| c as f64));
    let (a, b) = (DVec3::from_array(a), DVec3::from_array(b));
    field.water((a + b) * 0.5) > 0.0 && field.water(b) > 0.0
}

/// The distance from `from` (in the cave) to the cave's wall along `dir`, by sphere tracing
/// the karst's 1-Lipschitz field; `None` past `max` metres.
pub fn trace(field: &CarvedTerrain, from: DVec3, dir: DVec3, max: f64) -> Option<f64> {
    let mut t = 0.0;
    while t <= max {
        let d = field.cave(from + dir * t);
        if d > -0.01 {
            return Some(t);
        }
        t += (-d).max(0.01);
    }
    None
}

/// The speleothem of a station: its kind drawn, then its shape.
fn grow(field: &CarvedTerrain, s: &Station, p: &SdfParams, random: &mut Random) -> Option<Piece> {
    let height = s.roof - s.floor;
    let length = (p.speleothem_length * (0.5 * normal(random)).exp()).min(0.7 * height);
    let u = random.uniform();
    let (x, y) = (s.at.x, s.at.y);
    let at = |z: f64| [x as f32, y as f32, z as f32];
    let piece = |kind, a: [f32; 3], ra: f64, b: [f32; 3], rb: f64| {
        Some(Piece { kind, shape: Shape::Cone { a, ra: ra as f32, b, rb: rb as f32 } })
    };
    let floor_free = !s.stream;
    if u < 0.1 && floor_free && 2.0 * p.speleothem_length >= 0.7 * height {
        let r = (0.08 * height).clamp(0.08, 1.0);
        return piece(PieceKind::Column, at(s.floor - r), 1.4 * r, at(s.roof + r), r);
    }
    if u < 0.55 {
        let ra = 0.12 * length + 0.03;
        return piece(PieceKind::Stalactite, at(s.roof + ra), ra, at(s.roof - length), TIP);
    }
    if u < 0.85 && floor_free {
        let ra = 0.2 * length + 0.05;
        return piece(PieceKind::Stalagmite, at(s.floor - ra), ra, at(s.floor + length), 0.4 * ra);
    }
    flowstone(field, s, length, random)
}

/// Flowstone on the wall nearer one side of the station: a cone lying on the wall from a
/// point `length` above the station's height to one 1.5 `length` below, widening downwards.
fn flowstone(field: &CarvedTerrain, s: &Station, length: f64, random: &mut Random) -> Option<Piece> {
    let heading = random.range(0.0, std::f64::consts::TAU);
    let dir = DVec3::new(heading.cos(), heading.sin(), 0.0);
    let top_z = (s.at.z + length).min(s.roof - 0.1);
    let bottom_z = (s.at.z - 1.5 * length).max(s.floor + 0.1);
    if top_z - bottom_z < 0.3 {
        return None;
    }
    let wall = |z: f64| {
        let from = DVec3::new(s.at.x, s.at.y, z);
        if field.cave(from) > -0.05 {
            return None;
        }
        trace(field, from, dir, 20.0).map(|t| from + dir * t)
    };
    let (top, bottom) = (wall(top_z)?, wall(bottom_z)?);
    let (ra, rb) = (0.1 * length + 0.05, 0.35 * length + 0.1);
    if top.distance(bottom) <= rb - ra {
        return None;
    }
    let shape = Shape::Cone {
        a: top.as_vec3().to_array(),
        ra: ra as f32,
        b: bottom.as_vec3().to_array(),
        rb: rb as f32,
    };
    Some(Piece { kind: PieceKind::Flowstone, shape })
}

/// A standard normal deviate (Box–Muller).
pub fn normal(random: &mut Random) -> f64 {
    let u = random.uniform().max(f64::MIN_POSITIVE);
    (-2.0 * u.ln()).sqrt() * (std::f64::consts::TAU * random.uniform()).cos()
}
