//! The survey of a run: its stations placed along the skeleton (`stations.rs`), each measured
//! on the cave of the model (`measure.rs`, `area.rs`), the statistics of the measurements
//! beside the real caves' (`statistics.rs`) and the void volume.

use std::collections::BTreeMap;

use glam::DVec3;
use rayon::prelude::*;

use karst_sdf::{CarvedTerrain, Near, SdfModel};
use karst_skeleton::{ConduitType, Skeleton, Zone};

use crate::area::open_area;
use crate::error::SurveyError;
use crate::measure::{TOLERANCE, is_shaft, measure, plane};
use crate::payload::{Station, Survey, VoidVolume};
use crate::ranges::passage_ranges;
use crate::stations::{self, Placed, SPACING};
use crate::statistics::{counts, statistics};

/// How far from its centreline a station looks for an open passage, in the skeleton's
/// half-widths there (at least [`MIN_SEARCH`] metres).
const SEARCH: f64 = 3.0;
const MIN_SEARCH: f64 = 2.0;
/// How far outside the cave its bound is searched, metres. The survey reads the cave's
/// signed distance inside it (the steps of its chords) and its sign outside: with a reach
/// just above 0 the karst leaves farther than that from a point in rock are not visited
/// (`CarvedTerrain::cave_below_ground`), and every value read is the same as with no limit.
const CAVE_REACH: f64 = TOLERANCE;
/// How far outside the cave its bound is searched while a station's area is counted, in the
/// lattice's side: the bound's value at a point in rock decides the points of the lattice
/// nearer than it ([`open_area`]).
const AREA_REACH: f64 = 0.25;
/// Side of the lattice a station's area is counted on, in the larger of its two chords.
const AREA_SIDE: f64 = 2.0;

/// The survey of the cave `model` carved along `skeleton`.
pub fn build(skeleton: &Skeleton, model: &SdfModel) -> Result<Survey, SurveyError> {
    let field = CarvedTerrain::new(model.clone());
    let placed = stations::place(skeleton);
    let junctions = stations::junctions(skeleton);
    let stations: Vec<Station> = placed.par_iter().map(|p| survey_station(&field, p, &junctions)).collect();
    if !stations.iter().any(|s| s.width > 0.0) {
        let search = placed.iter().map(search_radius).fold(0.0, f64::max);
        return Err(SurveyError::NothingOpen { stations: stations.len(), search });
    }
    let lengths: Vec<f64> = skeleton.conduits.iter().map(|c| skeleton.conduit_length(c)).collect();
    Ok(Survey {
        spacing: SPACING,
        counted: stations.iter().filter(|s| counts(s)).count(),
        statistics: statistics(&stations, &passage_ranges()),
        void_volume: void_volume(&stations, &placed, &lengths),
        stations,
    })
}

fn search_radius(p: &Placed) -> f64 {
    (SEARCH * p.radius).max(MIN_SEARCH)
}

/// One station measured on the cave of `field`: chords, area, and whether it is near a junction.
fn survey_station(field: &CarvedTerrain, p: &Placed, junctions: &[DVec3]) -> Station {
    let search = search_radius(p);
    let around = Around::new(field, p.position, search + CHORD_BOX * p.radius, CAVE_REACH);
    let chords = measure(&|q| around.cave(q), p.position, p.tangent, search);
    let (width, height, area, centre) = match chords {
        Some(c) => {
            let side = AREA_SIDE * c.width.max(c.height);
            // The lattice's square, whatever its orientation, lies within its half diagonal.
            let around =
                Around::new(field, c.centre, side * std::f64::consts::FRAC_1_SQRT_2, side * AREA_REACH);
            (c.width, c.height, open_area(&|q| around.cave(q), c.centre, plane(p.tangent), side), c.centre)
        }
        None => (0.0, 0.0, 0.0, p.position),
    };
    let reach = if width > 0.0 { width } else { 2.0 * p.radius };
    let junction = junctions.iter().any(|j| j.distance(centre) < reach || j.distance(p.position) < reach);
    Station {
        conduit: p.conduit as u32 + 1,
        station: p.station,
        position: p.position.to_array(),
        width,
        height,
        area,
        kind: p.kind,
        zone: p.zone,
        shaft: is_shaft(p.tangent),
        junction,
    }
}

/// Half the side of the box whose karst leaves a station's chords gather, beyond the search for
/// an open point: in the skeleton's half-widths there. Points outside it (a chord running far
/// along a chamber) read the whole hierarchy.
const CHORD_BOX: f64 = 4.0;

/// The cave's bound around one point ([`CarvedTerrain::cave_below_ground`] searched up to
/// `reach` outside the cave): the karst leaves that can matter in a box around it gathered once,
/// as the mesher's bricks do, instead of a walk down the hierarchy at every point the chords and
/// the area read. Bit for bit the same values (`CarvedTerrain::near_cave`).
struct Around<'a> {
    field: &'a CarvedTerrain,
    near: Near,
    lo: DVec3,
    hi: DVec3,
    reach: f64,
}

impl<'a> Around<'a> {
    fn new(field: &'a CarvedTerrain, centre: DVec3, half: f64, reach: f64) -> Self {
        let (lo, hi) = (centre - DVec3::splat(half), centre + DVec3::splat(half));
        Around { field, near: field.near_cave(lo, hi, reach), lo, hi, reach }
    }

    fn cave(&self, p: DVec3) -> f64 {
        if p.cmpge(self.lo).all() && p.cmple(self.hi).all() {
            self.field.cave_below_ground_near(&self.near, p, self.reach)
        } else {
            self.field.cave_below_ground(p, self.reach)
        }
    }
}

/// Each station's area times the arc length it stands for (half the spacing on either side,
/// within its conduit), summed per zone and conduit type.
fn void_volume(stations: &[Station], placed: &[Placed], lengths: &[f64]) -> VoidVolume {
    let mut volume = VoidVolume {
        total: 0.0,
        zones: [Zone::Vadose, Zone::Phreatic].iter().map(|z| (zone_name(*z).to_string(), 0.0)).collect(),
        conduit_types: ConduitType::ALL
            .iter()
            .map(|t| (t.name().to_string(), 0.0))
            .collect::<BTreeMap<_, _>>(),
    };
    for (s, p) in stations.iter().zip(placed) {
        let length = lengths[p.conduit];
        let stands_for = (p.at + SPACING / 2.0).min(length) - (p.at - SPACING / 2.0).max(0.0);
        let v = s.area * stands_for.max(0.0);
        volume.total += v;
        *volume.zones.entry(zone_name(s.zone).to_string()).or_default() += v;
        *volume.conduit_types.entry(s.kind.name().to_string()).or_default() += v;
    }
    volume
}

/// The zone's name, as in the artifacts.
pub fn zone_name(zone: Zone) -> &'static str {
    match zone {
        Zone::Vadose => "vadose",
        Zone::Phreatic => "phreatic",
    }
}
