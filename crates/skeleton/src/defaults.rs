//! The network's defaults derived from the scene (issue 38; docs/skeleton.md, "Defaults from
//! the scene"). What `[skeleton]` leaves out of the tributaries and the meanders is computed
//! from the scene's own scales, so that a 300 m plateau and a 10 km massif both give networks
//! that pass for real caves:
//!
//! - the tributaries' lengths (`amplification_length`) from the sampling radius r (the shortest,
//!   2r, is the shortest branch the samples can draw) and the spacing of the sinks (the longest
//!   drains half the ground between two neighbouring sinks, within 10r–40r);
//! - their count (`amplification_points`) from the length of the routed network: one
//!   first-step tributary per [`JUNCTION_SPACING`] × r of conduit (seven per 30 r with the
//!   later steps), so that passages are cut into branches a few radii long at every scale;
//! - the meander wavelength (`meander_wavelength`) from the passage scale: ten passage widths
//!   (Leopold & Wolman 1960 for rivers, Deike & White 1969 for cave streams), the passage width
//!   being twice `skeleton.radius`;
//! - the joint sets the cost model assumes when the scene has no fracture family
//!   (`costgraph.assumed_joints`, [`karst_costgraph::assumed_joints`]), recorded as the
//!   `[[geology.fractures]]` a scene would give.
//!
//! The resolved values are what the rest of the stage reads (a copy of `[skeleton]` with every
//! derived field filled in) and are recorded in `skeleton.json` and `resolved.toml`.

use std::collections::BTreeMap;

use karst_sampling::Samples;
use karst_scene::params::SkeletonParams;
use karst_scene::{KeyPointKind, keypoints_of};

use crate::network::assemble::NetworkBuilder;
use crate::view::SkeletonView;

/// Conduit length per first-step tributary, in sampling radii. Chosen on the realism
/// population's tuning scenes (docs/metrics.md): with 10 the side passages cut every stretch
/// into pieces of one length (cv length below the real minimum on most dense-sink scenes),
/// 20, 30 and 40 left 85, 90 and 89 % of the realizations inside all ten ranges.
pub const JUNCTION_SPACING: f64 = 30.0;
/// Meander wavelength per passage width (ten widths, as rivers and cave streams).
const WAVELENGTH_PER_WIDTH: f64 = 10.0;

/// `[skeleton]` with every derived default filled in, and the values derived (field name →
/// value, `sampling.radius` included when `[sampling]` leaves it out).
#[derive(Debug, Clone)]
pub struct Resolved {
    pub params: SkeletonParams,
    pub derived: BTreeMap<String, serde_json::Value>,
}

/// The sampling radius of the scene, metres (given or derived).
pub fn sampling_radius(view: &SkeletonView) -> f64 {
    view.sampling.radius_metres(view.domain, view.terrain)
}

/// Resolves the defaults that depend on the scene alone: tributary lengths and meander
/// wavelengths (the tributary count waits for the routed network: [`Resolved::count`]).
pub fn resolve(view: &SkeletonView) -> Resolved {
    let mut params = view.skeleton.clone();
    let mut derived = BTreeMap::new();
    let r = sampling_radius(view);
    if view.sampling.radius.is_none() {
        derived.insert("sampling.radius".into(), round(r).into());
    }
    if params.amplification_length.is_none() {
        let longest = (sink_spacing(view) / 2.0).clamp(10.0 * r, 40.0 * r);
        let range = [round(2.0 * r), round(longest)];
        params.amplification_length = Some(range);
        derived.insert("skeleton.amplification_length".into(), range.to_vec().into());
    }
    if params.meander_wavelength.is_none() {
        let [lo, hi] = params.radius.map(|radius| round(2.0 * radius * WAVELENGTH_PER_WIDTH));
        let range = [lo, hi.max(lo)];
        params.meander_wavelength = Some(range);
        derived.insert("skeleton.meander_wavelength".into(), range.to_vec().into());
    }
    if view.geology.fractures.is_empty() && view.costgraph.assumed_joints {
        let families = karst_costgraph::assumed_joints(view.domain, view.terrain);
        let tables = families.iter().map(|f| serde_json::to_value(f).expect("a family serializes"));
        derived.insert("geology.fractures".into(), tables.collect::<Vec<_>>().into());
    }
    Resolved { params, derived }
}

impl Resolved {
    /// Fills in the tributary count from the routed network's length.
    pub fn count(&mut self, view: &SkeletonView, samples: &Samples, network: &NetworkBuilder) {
        if self.params.amplification_points.is_none() {
            let spacing = JUNCTION_SPACING * sampling_radius(view);
            let points = (routed_length(samples, network) / spacing).ceil() as usize;
            self.params.amplification_points = Some(points);
            self.derived.insert("skeleton.amplification_points".into(), points.into());
        }
    }
}

/// The median distance from a sink to its nearest other sink, horizontally; with one sink, its
/// distance to the nearest spring; with none, the domain's largest extent.
fn sink_spacing(view: &SkeletonView) -> f64 {
    let at = |kind| keypoints_of(view.keypoints, kind).map(|(_, k)| k.position).collect::<Vec<_>>();
    let (sinks, springs) = (at(KeyPointKind::Sink), at(KeyPointKind::Spring));
    let horizontal = |a: [f64; 3], b: [f64; 3]| (a[0] - b[0]).hypot(a[1] - b[1]);
    let others = if sinks.len() > 1 { &sinks } else { &springs };
    let mut nearest: Vec<f64> = sinks
        .iter()
        .enumerate()
        .filter_map(|(i, &s)| {
            others
                .iter()
                .enumerate()
                .filter(|&(j, _)| sinks.len() == 1 || j != i)
                .map(|(_, &o)| horizontal(s, o))
                .min_by(f64::total_cmp)
        })
        .collect();
    if nearest.is_empty() {
        return view.domain.size().max_element();
    }
    nearest.sort_by(f64::total_cmp);
    nearest[nearest.len() / 2]
}

/// Total length of the network's links, metres.
fn routed_length(samples: &Samples, network: &NetworkBuilder) -> f64 {
    let at = |i: u32| glam::DVec3::from_array(samples.positions[network.samples[i as usize] as usize]);
    let doubled: f64 = network
        .adjacency
        .iter()
        .enumerate()
        .flat_map(|(i, next)| next.iter().map(move |&j| (i as u32, j)))
        .map(|(i, j)| at(i).distance(at(j)))
        .sum();
    doubled / 2.0
}

/// To the centimetre: the values are printed and recorded.
fn round(v: f64) -> f64 {
    (v * 100.0).round() / 100.0
}
