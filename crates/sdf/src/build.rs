//! Building the construction tree from the skeleton and the flows (Paris et al. 2021 §6.2):
//!
//! - each node gets a cross-section: the shapes of the types of the segments meeting there,
//!   half and half, at the node's radius; along a segment the section moves linearly from one
//!   node's to the next, or, when the conduit has a passage profile (`[sdf] passage_detail`),
//!   through the section of each profile point between them (the segment's type at the
//!   profile's radius and ratio), one sweep from each to the next;
//! - with passage profiles, every conduit becomes one sweep per segment through its profile's
//!   sections, each run on past its nodes so that the sweeps meet as mitred joints
//!   ([`crate::mitre`]): the profile's sections (canyons, beds, keyholes) keep their shapes
//!   through the bends, and a tortuous passage costs a leaf per segment, not thousands of
//!   spheres filling its sections out to their corners;
//! - without (`[sdf] passage_detail = "off"`, the paper's construction), a conduit whose
//!   tortuosity (1 − chord/length) is at most `sdf.tortuosity` becomes one sweep per segment,
//!   plus a sphere inscribed at each inner node to close the bends;
//! - and a more tortuous one a union of spheres: cross-sections are placed along it
//!   every `sdf.sphere_spacing` radii (along a passage profile, the local half-thickness), oriented by the curve's tangent (averaged at the nodes);
//!   sphere centres are drawn on a jittered lattice of the same spacing in each section plane
//!   and kept when at least half a spacing (the paper's R/2 selection) and `MIN_DEPTH` times
//!   the section's deepest candidate inside it; each sphere is inscribed (its radius is the centre's depth in the
//!   section), and spheres inside a bigger kept one (grown by `COVER` spacings) are dropped;
//! - `chamber` segments become noise-biased chambers around the segment;
//! - every wet segment also gets its water piece ([`crate::water::conduits`]).

use glam::{DVec2, DVec3};

use karst_hydro::Hydro;
use karst_scene::params::SdfParams;
use karst_scene::rng::Random;
use karst_skeleton::{Conduit, ConduitType, Skeleton};

use crate::error::SdfError;
use crate::mitre::{self, Junctions};
use crate::payload::{SdfModel, SphereGroup, TypedSweep, WaterSpec};
use crate::tree::chamber::ChamberSpec;
use crate::tree::noise::WaveNoise;
use crate::tree::section::{Section, Shape};
use crate::tree::sweep::{SectionSpec, SweepSpec, frame, tortuosity};
use crate::tree::terrain::TerrainField;
use crate::view::SdfView;
use crate::water::conduits::{self, Water};

/// The model of the scene carved by the conduits of `skeleton`, with the water of `hydro`.
pub fn build(view: &SdfView, skeleton: &Skeleton, hydro: &Hydro) -> Result<SdfModel, SdfError> {
    crate::estimate::check(view, skeleton)?;
    if hydro.conduits.len() != skeleton.conduits.len() {
        return Err(SdfError::ConduitCounts {
            hydro: hydro.conduits.len(),
            skeleton: skeleton.conduits.len(),
        });
    }
    let terrain = TerrainField::of(view.terrain);
    let lambda = terrain.lipschitz();
    if !lambda.is_finite() {
        return Err(SdfError::TerrainNotLipschitz { lambda });
    }
    let p = view.sdf;
    let mut model = SdfModel::new(*view.domain, terrain);
    model.blend = p.blend;
    model.detail = p.detail;
    model.chamber_bias = p.chamber_bias;
    model.detail_noise =
        WaveNoise::draw(&mut Random::stream(view.seed, "sdf", "detail"), p.detail_wavelength);
    let mean_radius = mean_radius(skeleton) * p.radius_scale;
    model.chamber_noise =
        WaveNoise::draw(&mut Random::stream(view.seed, "sdf", "chamber"), mean_radius * p.chamber_scale);
    let mut lean = Random::stream(view.seed, "sdf", "asymmetry");
    let mut jitter = Random::stream(view.seed, "sdf", "spheres");
    // With passage profiles every conduit is swept, its bends mitred.
    let profiled = p.passage_detail.varies();
    let junctions = profiled.then(|| Junctions::of(skeleton));
    let progress = karst_stage::progress::bar(skeleton.conduits.len() as u64, "sdf");
    for (c, conduit) in skeleton.conduits.iter().enumerate() {
        let points = conduit_points(skeleton, conduit);
        let asymmetry = if lean.uniform() < 0.5 { -p.asymmetry } else { p.asymmetry };
        let at_nodes = conduit.node_profile_points(&arc_lengths(&points));
        let sections = node_sections(p, conduit, c, &at_nodes, asymmetry)?;
        let pieces = passage_pieces(p, conduit, c, &points, &sections, &at_nodes, asymmetry)?;
        let tortuous = !profiled && tortuosity(&points) > p.tortuosity && points.len() > 2;
        let run_ons = match &junctions {
            Some(junctions) => mitre::run_ons(&points, &sections, junctions.continuations(skeleton, c)),
            None => vec![[0.0; 2]; pieces.len()],
        };
        for (i, segment) in pieces.iter().enumerate() {
            let kind = conduit.types[i];
            let zones = [conduit.nodes[i], conduit.nodes[i + 1]].map(|n| skeleton.nodes[n as usize].zone);
            let wet = hydro.conduits[c].segments.get(i).ok_or_else(|| segments_mismatch(c))?;
            if kind == ConduitType::Chamber {
                let radius = segment.iter().map(|(_, _, s)| s.shape.radius).fold(0.0, f32::max);
                model.chambers.push(ChamberSpec {
                    a: to_f32(points[i]),
                    b: to_f32(points[i + 1]),
                    radius: radius * p.chamber_scale as f32,
                });
            }
            if kind != ConduitType::Chamber && !tortuous {
                let run = run_on(segment, run_ons[i]);
                let sweeps = run.windows(2).map(|w| sweep_of(w[0], w[1]));
                model.sweeps.extend(sweeps.enumerate().map(|(k, sweep)| TypedSweep {
                    kind,
                    continues: k > 0,
                    sweep,
                }));
            }
            for w in segment.windows(2) {
                let sweep = sweep_of(w[0], w[1]);
                let height = sweep.floor().abs() * 2.0;
                let segment = conduits::Segment { kind, zones, water: wet.water, depth: wet.depth, height };
                if let Some(spec) = water_piece(&sweep, conduits::level(&segment)) {
                    model.water.push(spec);
                }
            }
        }
        if tortuous {
            model.spheres.extend(sphere_groups(conduit, &points, &pieces, p.sphere_spacing, &mut jitter));
        } else if !profiled {
            model.spheres.extend(joint_spheres(conduit, &points, &sections));
        }
        progress.inc(1);
    }
    progress.finish_and_clear();
    if p.passage_detail.features() {
        crate::detail::place::add(&mut model, p, view.seed, skeleton, hydro);
    }
    Ok(model)
}

fn segments_mismatch(conduit: usize) -> SdfError {
    SdfError::WaterSegments { conduit }
}

fn mean_radius(skeleton: &Skeleton) -> f64 {
    let radii: Vec<f64> =
        skeleton.conduits.iter().flat_map(|c| c.radius.iter().copied()).filter(|r| r.is_finite()).collect();
    if radii.is_empty() { 1.0 } else { radii.iter().sum::<f64>() / radii.len() as f64 }
}

/// The conduit's node positions (checked by `Skeleton::validate`: existing, finite, distinct
/// consecutive nodes).
fn conduit_points(skeleton: &Skeleton, conduit: &Conduit) -> Vec<DVec3> {
    conduit.nodes.iter().map(|&n| DVec3::from_array(skeleton.nodes[n as usize].position)).collect()
}

/// The section of each node of the conduit, checked (radius > 0, no self-intersection).
fn node_sections(
    p: &SdfParams,
    conduit: &Conduit,
    c: usize,
    at_nodes: &[usize],
    asymmetry: f64,
) -> Result<Vec<SectionSpec>, SdfError> {
    let last = conduit.types.len().saturating_sub(1);
    let ratio = |i: usize| at_nodes.get(i).map_or(1.0, |&k| conduit.profile[k].ratio);
    (0..conduit.nodes.len())
        .map(|i| {
            let kinds = [conduit.types[i.saturating_sub(1).min(last)], conduit.types[i.min(last)]];
            checked_section(p, c, i, kinds, conduit.radius[i], ratio(i), asymmetry)
        })
        .collect()
}

/// The arc length of each point from the first, metres.
fn arc_lengths(points: &[DVec3]) -> Vec<f64> {
    let mut at = vec![0.0];
    for w in points.windows(2) {
        at.push(at[at.len() - 1] + w[0].distance(w[1]));
    }
    at
}

/// The section of types `kinds` at radius `radius` and profile ratio `ratio` (times the
/// scene's `sdf.radius_scale` and `sdf.ratio`), checked.
fn checked_section(
    p: &SdfParams,
    c: usize,
    node: usize,
    kinds: [ConduitType; 2],
    radius: f64,
    ratio: f64,
    asymmetry: f64,
) -> Result<SectionSpec, SdfError> {
    // Radii within [1e-6, 1e9] (Skeleton::validate) times a scale within [1e-3, 1e3].
    let radius = radius * p.radius_scale;
    let ratio = p.ratio * ratio;
    let shape = Shape { radius: radius as f32, ratio: ratio as f32, asymmetry: asymmetry as f32 };
    let spec = SectionSpec { kinds, shape };
    spec.section().check().map_err(|problem| SdfError::BadSection {
        ratio,
        asymmetry,
        conduit: c,
        node,
        types: kinds.map(|k| k.name()),
        problem: problem.to_string(),
    })?;
    Ok(spec)
}

/// A point of a segment's passage: its fraction of the segment, its position and its section.
type Piece = (f64, DVec3, SectionSpec);

/// The passage along each segment of the conduit, from its start node to its end node: the two
/// node sections, and with a profile the section at each profile point in between (the
/// segment's own type, the profile's size and shape).
fn passage_pieces(
    p: &SdfParams,
    conduit: &Conduit,
    c: usize,
    points: &[DVec3],
    sections: &[SectionSpec],
    at_nodes: &[usize],
    asymmetry: f64,
) -> Result<Vec<Vec<Piece>>, SdfError> {
    (0..points.len() - 1)
        .map(|i| {
            let (a, b) = (points[i], points[i + 1]);
            let mut pieces = vec![(0.0, a, sections[i])];
            if let (Some(&start), Some(&end)) = (at_nodes.get(i), at_nodes.get(i + 1)) {
                let (s0, s1) = (conduit.profile[start].at, conduit.profile[end].at);
                for point in conduit.profile.get(start + 1..end).unwrap_or_default() {
                    let t = (point.at - s0) / (s1 - s0);
                    let kind = conduit.types[i];
                    let spec = checked_section(p, c, i, [kind, kind], point.radius, point.ratio, asymmetry)?;
                    pieces.push((t, a.lerp(b, t), spec));
                }
            }
            pieces.push((1.0, b, sections[i + 1]));
            Ok(pieces)
        })
        .collect()
}

/// The sweep from one passage point to the next.
fn sweep_of(from: Piece, to: Piece) -> SweepSpec {
    SweepSpec { a: to_f32(from.1), b: to_f32(to.1), start: from.2, end: to.2 }
}

/// A segment's passage points with its run-ons ([`mitre::run_ons`]): the start section held
/// over `before` metres ahead of the start node and the end section over `after` metres past
/// the end node (none when shorter than a millimetre).
fn run_on(segment: &[Piece], [before, after]: [f64; 2]) -> Vec<Piece> {
    let (first, last) = (segment[0], segment[segment.len() - 1]);
    let length = first.1.distance(last.1);
    let way = (last.1 - first.1) / length;
    let mut run = Vec::with_capacity(segment.len() + 2);
    if before >= MIN_RUN_ON {
        run.push((-before / length, first.1 - way * before, first.2));
    }
    run.extend_from_slice(segment);
    if after >= MIN_RUN_ON {
        run.push((1.0 + after / length, last.1 + way * after, last.2));
    }
    run
}

/// Run-ons shorter than this (metres) are left out.
const MIN_RUN_ON: f64 = 1e-3;

fn water_piece(sweep: &SweepSpec, water: Water) -> Option<WaterSpec> {
    match water {
        Water::None => None,
        Water::Flooded => Some(WaterSpec { sweep: *sweep, level: None }),
        Water::Stream { depth } => {
            let floor = sweep.floor();
            Some(WaterSpec { sweep: *sweep, level: Some((floor + depth) as f32) })
        }
    }
}

/// Spheres inscribed at the inner nodes of a swept conduit without a passage profile, closing
/// the wedges that flat-capped sweeps leave on the outside of bends.
fn joint_spheres(conduit: &Conduit, points: &[DVec3], sections: &[SectionSpec]) -> Option<SphereGroup> {
    let spheres: Vec<[f32; 4]> = (1..points.len().saturating_sub(1))
        .filter_map(|i| {
            let depth = -sections[i].section().distance(DVec2::ZERO);
            let p = to_f32(points[i]);
            (depth > 0.0).then_some([p[0], p[1], p[2], depth as f32])
        })
        .collect();
    (!spheres.is_empty()).then(|| SphereGroup { kind: dominant(&conduit.types), spheres })
}

/// The most frequent type (ties to the first in [`ConduitType::ALL`]).
fn dominant(types: &[ConduitType]) -> ConduitType {
    ConduitType::ALL
        .into_iter()
        .max_by_key(|k| (types.iter().filter(|t| *t == k).count(), std::cmp::Reverse(*k)))
        .unwrap_or(ConduitType::Tube)
}

/// Smallest sphere radius, as a fraction of the deepest candidate of its cross-section: the
/// spheres hug the section's medial axis, and wall features finer than that are rounded off.
const MIN_DEPTH: f64 = 0.6;

/// A candidate is dropped when a kept sphere grown by this fraction of the spacing contains it:
/// the union then differs from the kept spheres' by less than that.
const COVER: f64 = 0.15;

/// A candidate sphere: centre, radius, station.
struct Candidate {
    centre: DVec3,
    radius: f64,
    station: usize,
}

/// The spheres of a tortuous conduit, one group per segment type run.
fn sphere_groups(
    conduit: &Conduit,
    points: &[DVec3],
    pieces: &[Vec<Piece>],
    spacing: f64,
    jitter: &mut Random,
) -> Vec<SphereGroup> {
    let tangents = node_tangents(points);
    let mut groups: Vec<SphereGroup> = Vec::new();
    for (i, w) in points.windows(2).enumerate() {
        let kind = conduit.types[i];
        if kind == ConduitType::Chamber {
            continue;
        }
        let smallest = pieces[i].iter().map(|(_, _, s)| s.shape.radius).fold(f32::INFINITY, f32::min);
        let step = spacing * smallest as f64;
        let mut candidates = Vec::new();
        // The end station belongs to the next segment, except for the last one.
        let last = i + 2 == points.len();
        for (j, (t, local)) in
            stations(&pieces[i], w[0].distance(w[1]), spacing, last).into_iter().enumerate()
        {
            let origin = w[0].lerp(w[1], t);
            let tangent = tangents[i].lerp(tangents[i + 1], t).normalize();
            let section = section_at(&pieces[i], t);
            station_spheres(&section, origin, tangent, local, j, jitter, &mut candidates);
        }
        let spheres = prune(candidates, step);
        match groups.last_mut() {
            Some(g) if g.kind == kind => g.spheres.extend(spheres),
            _ => groups.push(SphereGroup { kind, spheres }),
        }
    }
    groups
}

/// The stations of a segment of `length` metres: each fraction along it with its step, metres.
/// Between two node sections alone (no passage profile) the stations are evenly spaced at
/// `spacing` times the smaller radius. Along a passage profile each station is `spacing` times
/// the local half-thickness (the depth of the section's axis point, the radius of the largest
/// sphere there) past the one before: a pinch or a low bedding-plane passage is sampled finely
/// without sampling the rooms around it as finely, so the spheres' count follows the passage's
/// length over its local size, not over its least size.
fn stations(pieces: &[Piece], length: f64, spacing: f64, last: bool) -> Vec<(f64, f64)> {
    let mut out = Vec::new();
    if pieces.len() == 2 {
        let smallest = pieces.iter().map(|(_, _, s)| s.shape.radius).fold(f32::INFINITY, f32::min);
        let step = spacing * smallest as f64;
        let count = (length / step).ceil().max(1.0) as usize;
        let end = if last { count } else { count - 1 };
        out.extend((0..=end).map(|j| (j as f64 / count as f64, step)));
        return out;
    }
    let step_at = |t: f64| {
        let section = section_at(pieces, t);
        let depth = -section.distance(DVec2::ZERO);
        spacing * if depth > 0.0 { depth } else { section.extent() }
    };
    let mut t = 0.0;
    while t < 1.0 {
        let step = step_at(t);
        out.push((t, step));
        t += step / length;
    }
    if last {
        out.push((1.0, step_at(1.0)));
    }
    out
}

/// The section at fraction `t` of a segment: linear between the pieces around it.
fn section_at(pieces: &[Piece], t: f64) -> Section {
    let k = pieces.partition_point(|(u, _, _)| *u <= t).clamp(1, pieces.len() - 1);
    let ((t0, _, s0), (t1, _, s1)) = (pieces[k - 1], pieces[k]);
    let f = if t1 > t0 { ((t - t0) / (t1 - t0)).clamp(0.0, 1.0) } else { 0.0 };
    s0.section().lerp(&s1.section(), f)
}

/// Unit tangents at the nodes: the segment direction at the ends, the mean of the two
/// adjacent directions inside.
fn node_tangents(points: &[DVec3]) -> Vec<DVec3> {
    let dirs: Vec<DVec3> = points.windows(2).map(|w| (w[1] - w[0]).normalize()).collect();
    (0..points.len())
        .map(|i| {
            let before = dirs[i.saturating_sub(1).min(dirs.len() - 1)];
            let after = dirs[i.min(dirs.len() - 1)];
            let mean = before + after;
            if mean.length_squared() > 1e-12 { mean.normalize() } else { after }
        })
        .collect()
}

/// Inscribed-sphere candidates of one cross-section on a jittered lattice of spacing `step`.
fn station_spheres(
    section: &Section,
    origin: DVec3,
    tangent: DVec3,
    step: f64,
    station: usize,
    jitter: &mut Random,
    out: &mut Vec<Candidate>,
) {
    let (right, up) = frame(tangent);
    let extent = section.extent();
    let cells = (extent / step).ceil() as i64;
    let mut lattice = Vec::new();
    for y in -cells..=cells {
        for x in -cells..=cells {
            let q = DVec2::new(x as f64 + jitter.range(-0.4, 0.4), y as f64 + jitter.range(-0.4, 0.4)) * step;
            // Beyond the extent the point is outside the section.
            if q.length() < extent {
                lattice.push((q, -section.distance(q)));
            }
        }
    }
    let deepest = lattice.iter().map(|c| c.1).fold(0.0, f64::max);
    let min_depth = (step * 0.5).max(MIN_DEPTH * deepest);
    for (q, depth) in lattice {
        if depth >= min_depth {
            out.push(Candidate { centre: origin + right * q.x + up * q.y, radius: depth, station });
        }
    }
}

/// Drops the spheres contained in a bigger kept one (checked against nearby stations only:
/// a sphere can only contain spheres within its radius).
fn prune(mut candidates: Vec<Candidate>, step: f64) -> Vec<[f32; 4]> {
    candidates.sort_by(|a, b| b.radius.total_cmp(&a.radius).then(a.station.cmp(&b.station)));
    let largest = candidates.first().map_or(0.0, |c| c.radius);
    let reach = (largest / step).ceil() as usize + 1;
    let stations = candidates.iter().map(|c| c.station).max().map_or(0, |s| s + 1);
    let mut kept: Vec<Vec<usize>> = vec![Vec::new(); stations];
    let mut order = Vec::new();
    for (k, c) in candidates.iter().enumerate() {
        let lo = c.station.saturating_sub(reach);
        let hi = (c.station + reach).min(stations - 1);
        let inside = (lo..=hi).flat_map(|s| &kept[s]).any(|&o| {
            let big = &candidates[o];
            big.centre.distance(c.centre) + c.radius <= big.radius + COVER * step
        });
        if !inside {
            kept[c.station].push(k);
            order.push(k);
        }
    }
    order.sort_unstable();
    order
        .into_iter()
        .map(|k| {
            let c = &candidates[k];
            let p = to_f32(c.centre);
            [p[0], p[1], p[2], c.radius as f32]
        })
        .collect()
}

fn to_f32(p: DVec3) -> [f32; 3] {
    p.as_vec3().to_array()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::synthetic;
    use karst_scene::params::PassageDetail;
    use karst_scene::{Scene, SceneView};
    use karst_stage::{Blame, Failure};

    fn build_with(edit: impl FnOnce(&mut Scene, &mut Skeleton)) -> Result<SdfModel, SdfError> {
        let mut scene = Scene::parse(synthetic::SCENE, std::path::Path::new("synthetic.toml")).unwrap();
        let (mut skeleton, hydro) = synthetic::network(2, 6, 5);
        edit(&mut scene, &mut skeleton);
        build(&SdfView::of(&scene), &skeleton, &hydro)
    }

    #[test]
    fn bad_radii_and_nodes_are_refused_when_the_skeleton_is_read() {
        use karst_artifact::Payload;
        let field = |edit: &dyn Fn(&mut Skeleton)| {
            let (mut skeleton, _) = synthetic::network(2, 6, 5);
            edit(&mut skeleton);
            skeleton.validate().expect_err("invalid").field
        };
        for bad in [0.0, -1.0, f64::NAN, f64::INFINITY] {
            assert_eq!(field(&|s| s.conduits[2].radius[1] = bad), "conduits[2].radius[1]");
        }
        assert_eq!(field(&|s| s.nodes[3].position[1] = f64::NAN), "nodes[3].position");
        assert_eq!(field(&|s| s.conduits[0].nodes[1] = 9999), "conduits[0].nodes[1]");
        assert_eq!(field(&|s| s.conduits[1].types.clear()), "conduits[1].types");
    }

    #[test]
    fn a_terrain_without_a_lipschitz_bound_is_the_scene_s_fault() {
        let e = build_with(|scene, _| {
            *scene.terrain_mut() = karst_geology::Terrain::Plane {
                elevation: 190.0,
                origin: [0.0, 0.0],
                gradient: [f64::INFINITY, 0.0],
            }
        })
        .unwrap_err();
        assert!(matches!(e, SdfError::TerrainNotLipschitz { .. }), "{e}");
        assert_eq!(e.blame(), Blame::Scene);
    }

    #[test]
    fn without_profiles_a_straight_conduit_is_swept_and_a_winding_one_is_spheres() {
        let off = |scene: &mut Scene, _: &mut Skeleton| scene.sdf_mut().passage_detail = PassageDetail::Off;
        let model = build_with(off).unwrap();
        assert!(!model.sweeps.is_empty() && !model.spheres.is_empty());
        let straight = [DVec3::ZERO, DVec3::new(10.0, 0.0, 0.0), DVec3::new(20.0, 0.1, 0.0)];
        assert!(tortuosity(&straight) < 1e-3);
        let winding = [
            DVec3::ZERO,
            DVec3::new(10.0, 0.0, 0.0),
            DVec3::new(10.0, 10.0, 0.0),
            DVec3::new(0.0, 10.0, 0.0),
        ];
        assert!((tortuosity(&winding) - (1.0 - 10.0 / 30.0)).abs() < 1e-12);
    }

    #[test]
    fn a_sweep_that_continues_no_run_is_refused_when_the_model_is_read() {
        use karst_artifact::Payload;
        let model = build_with(|_, _| {}).unwrap();
        model.validate().unwrap();
        let mut first = model.clone();
        first.sweeps[0].continues = true;
        assert_eq!(first.validate().unwrap_err().field, "sweeps[0].continues");
        let second = (1..model.sweeps.len()).find(|&k| !model.sweeps[k].continues).expect("two runs");
        let mut elsewhere = model.clone();
        elsewhere.sweeps[second].continues = true;
        let e = elsewhere.validate().unwrap_err();
        assert_eq!(e.field, format!("sweeps[{second}].continues"), "{e:?}");
    }

    /// A profiled conduit turning a right angle: the outside corner of the bend, beyond the
    /// sphere a joint would inscribe at the node, is cave (the two legs run on as a mitre), and
    /// the rock past the mitre's corner stays rock.
    #[test]
    fn a_right_angle_bend_is_mitred_on_its_outside() {
        let model = build_with(|scene, skeleton| {
            scene.sdf_mut().passage_detail = PassageDetail::Passages;
            scene.sdf_mut().detail = 0.0;
            let conduit = &mut skeleton.conduits[0];
            conduit.radius.iter_mut().for_each(|r| *r = 2.0);
            conduit.types.iter_mut().for_each(|t| *t = ConduitType::Tube);
            let corner = [[500.0, 500.0, 120.0], [530.0, 500.0, 120.0], [530.0, 530.0, 120.0]];
            for (node, at) in conduit.nodes.iter().zip(corner) {
                skeleton.nodes[*node as usize].position = at;
            }
            // The rest of the conduit goes on straight up the second leg.
            for (k, node) in conduit.nodes.iter().enumerate().skip(3) {
                skeleton.nodes[*node as usize].position = [530.0, 530.0 + 20.0 * (k - 2) as f64, 120.0];
            }
        })
        .unwrap();
        let field = crate::CarvedTerrain::new(model);
        let outside_corner = DVec3::new(531.6, 498.4, 120.0);
        assert!(outside_corner.distance(DVec3::new(530.0, 500.0, 120.0)) > 2.2, "beyond a joint sphere");
        assert!(field.cave(outside_corner) < 0.0, "{}", field.cave(outside_corner));
        assert!(field.cave(DVec3::new(533.0, 497.0, 120.0)) > 0.0);
    }

    #[test]
    fn the_model_is_deterministic() {
        assert_eq!(build_with(|_, _| {}).unwrap(), build_with(|_, _| {}).unwrap());
    }
}
