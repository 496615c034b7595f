//! Amplification (Paris et al. 2021 §5.2, KarstNSim §4.6): after the main network is drawn,
//! `skeleton.amplification_steps` times, new key points are drawn in the bedrock and joined to
//! the network by least-cost paths:
//!
//! - a dead end (probability `skeleton.dead_end_fraction`) is joined once, to the cheapest
//!   network node;
//! - an interior point is joined twice: to the cheapest network node n₁, then to the cheapest
//!   network node farther than twice |p − n₁| from n₁, so that the second path reaches another
//!   part of the network and closes a loop (when no such node is reachable, the point stays a
//!   dead end).
//!
//! New passages meet the network along a conduit, at a T-junction: existing junctions and key
//! points are closed to the join (a passage reaching exactly an existing junction is a
//! coincidence, and real caves rarely have more than three passages meeting; Paris et al.
//! §7.3). Only when no conduit node can be reached does the join take any network node.
//!
//! Where the points are drawn:
//!
//! - without `skeleton.amplification_length`, `skeleton.amplification_points` points per step
//!   uniformly in the network's bounding box (Paris et al.);
//! - with it, as tributaries at several scales (Horton's laws of stream networks, which
//!   branchwork caves follow too): step s draws `amplification_points` × R^s points
//!   (R = `skeleton.amplification_ratio`), each at a distance ℓ from an anchor on the network,
//!   ℓ following a power law P(ℓ > x) ∝ x^−α (α = `skeleton.amplification_exponent`) truncated to
//!   [min, max / R^s] of `amplification_length`, in a uniformly random direction. Small
//!   passages are many and short, large ones few and long: a heavy-tailed size distribution
//!   like that of the inlets and side passages of real caves. With R > 1, the anchors of step
//!   s lie on the branches of step s − 1 (tributaries of tributaries); with R = 1 anywhere on
//!   the network. With probability `skeleton.confluence_attraction` the anchor is instead one
//!   of the confluences where the previous step's branches joined (at first: the network's
//!   junctions): water of different origins mixes there and is aggressive again (mixing
//!   corrosion, Bögli 1964), and junctions sit on fracture intersections, so side passages
//!   cluster at confluences while long stretches of passage between them stay unbroken.
//!
//! Each new point is snapped to its nearest sample, so it lies in the bedrock. No route uses
//! these branches: they are dry in the flow stage.

use glam::DVec3;
use karst_costgraph::CostGraph;
use karst_sampling::Samples;
use karst_scene::KeyPointKind;
use karst_scene::params::SkeletonMode;
use karst_scene::rng::Random;

use crate::error::SkeletonError;
use crate::network::assemble::NetworkBuilder;
use crate::network::nodes::is_keypoint;
use crate::network::shape::planes::bedding_normal;
use crate::route::ends::{End, sample_of};
use crate::route::search::{Blocked, EdgeCosts, dijkstra_to_set};
use crate::view::SkeletonView;

/// Tries to draw one point inside the bedrock before giving up on it.
const TRIES: usize = 64;

/// Joins the key points the mode did not route: dead ends once (both modes) and, in karstnsim
/// mode, waypoints twice, like amplification's dead ends and interior points. Errors name a
/// key point that cannot reach the network.
pub fn join_keypoints(
    view: &SkeletonView,
    samples: &Samples,
    graph: &CostGraph,
    network: &mut NetworkBuilder,
) -> Result<(), SkeletonError> {
    let waypoints_routed = view.skeleton.mode == SkeletonMode::Gamma;
    for (index, k) in view.keypoints.iter().enumerate() {
        let dead_end = match k.kind {
            KeyPointKind::DeadEnd => true,
            KeyPointKind::Waypoint if !waypoints_routed => false,
            _ => continue,
        };
        let end = End { row: index, keypoint: index, name: &k.name };
        let start = sample_of(samples, &end)?;
        if join(samples, graph, network, start, dead_end).is_none() {
            return Err(SkeletonError::KeyPointOffNetwork { name: k.name.clone() });
        }
    }
    Ok(())
}

/// Adds the amplification branches to `network`.
pub fn amplify(view: &SkeletonView, samples: &Samples, graph: &CostGraph, network: &mut NetworkBuilder) {
    let p = view.skeleton;
    let mut rng = Random::stream(view.seed, "skeleton", "amplification");
    let mut parents: Vec<usize> = (0..network.samples.len()).collect();
    let mut confluences = junctions(network);
    for step in 0..p.amplification_steps {
        let (lo, hi) = bounding_box(samples, network);
        let scale = p.amplification_ratio.powi(step as i32);
        let before = network.samples.len();
        let mut joined = Vec::new();
        for _ in 0..(p.amplification_points.unwrap_or(0) as f64 * scale).round() as usize {
            let dead_end = rng.uniform() < p.dead_end_fraction;
            let point = match p.amplification_length {
                Some([min, max]) => {
                    let anchor = if !confluences.is_empty() && rng.uniform() < p.confluence_attraction {
                        confluences[rng.index(confluences.len())]
                    } else {
                        parents[rng.index(parents.len())]
                    };
                    let length = power_law(&mut rng, min, (max / scale).max(min), p.amplification_exponent);
                    draw_tributary(view, samples, network, &mut rng, anchor, length)
                }
                None => draw_in_bedrock(view, &mut rng, lo, hi),
            };
            let Some(point) = point else { continue };
            let start = nearest_sample(samples, point);
            joined.extend(join(samples, graph, network, start, dead_end).unwrap_or_default());
        }
        if p.amplification_ratio > 1.0 && network.samples.len() > before {
            parents = (before..network.samples.len()).collect();
            confluences = joined;
        } else {
            parents = (0..network.samples.len()).collect();
            confluences = junctions(network);
        }
    }
}

/// The network's junctions (nodes with three links or more).
fn junctions(network: &NetworkBuilder) -> Vec<usize> {
    (0..network.samples.len()).filter(|&i| network.adjacency[i].len() >= 3).collect()
}

/// Joins sample `start` to the network once (dead end) or twice (interior point); returns the
/// network nodes it joined at (none when it already lies on the network), or None when it
/// cannot reach the network.
fn join(
    samples: &Samples,
    graph: &CostGraph,
    network: &mut NetworkBuilder,
    start: usize,
    dead_end: bool,
) -> Option<Vec<usize>> {
    let on_network = network_mask(samples, network);
    if on_network[start] {
        return Some(Vec::new());
    }
    let mut closed = vec![false; samples.len()];
    for (i, &s) in network.samples.iter().enumerate() {
        closed[s as usize] = network.adjacency[i].len() != 2 || is_keypoint(samples, s);
    }
    let conduit = |v: usize| on_network[v] && !closed[v];
    let t_junctions = Blocked { base: graph, blocked: &closed };
    let (mut tree, mut first) = dijkstra_to_set(&t_junctions, start, conduit);
    let costs: &dyn EdgeCosts = if first.is_some() {
        &t_junctions
    } else {
        (tree, first) = dijkstra_to_set(graph, start, |v| on_network[v]);
        graph
    };
    let first = first?;
    let mut joined = vec![first];
    let path = tree.path(first).expect("reached");
    if !dead_end {
        let at = |v: usize| DVec3::from_array(samples.positions[v]);
        let far = 2.0 * at(start).distance(at(first));
        let target = |v: usize| on_network[v] && !closed[v] && at(v).distance(at(first)) > far;
        let (tree, second) = dijkstra_to_set(costs, start, target);
        if let Some(second) = second {
            network.add_path(&tree.path(second).expect("reached"));
            joined.push(second);
        }
    }
    network.add_path(&path);
    Some(joined.iter().map(|&s| network.node_of(s).expect("on the network") as usize).collect())
}

fn network_mask(samples: &Samples, network: &NetworkBuilder) -> Vec<bool> {
    let mut mask = vec![false; samples.len()];
    for &s in &network.samples {
        mask[s as usize] = true;
    }
    mask
}

fn bounding_box(samples: &Samples, network: &NetworkBuilder) -> (DVec3, DVec3) {
    network
        .samples
        .iter()
        .map(|&s| DVec3::from_array(samples.positions[s as usize]))
        .fold((DVec3::splat(f64::INFINITY), DVec3::splat(f64::NEG_INFINITY)), |(lo, hi), p| {
            (lo.min(p), hi.max(p))
        })
}

fn draw_in_bedrock(view: &SkeletonView, rng: &mut Random, lo: DVec3, hi: DVec3) -> Option<DVec3> {
    (0..TRIES).find_map(|_| {
        let p = DVec3::new(rng.range(lo.x, hi.x), rng.range(lo.y, hi.y), rng.range(lo.z, hi.z));
        view.in_bedrock(p).then_some(p)
    })
}

/// A length on [min, max] with P(ℓ > x) ∝ x^−α (truncated Pareto, by inversion).
fn power_law(rng: &mut Random, min: f64, max: f64, alpha: f64) -> f64 {
    let (a, b) = (min.powf(-alpha), max.powf(-alpha));
    (a - rng.uniform() * (a - b)).powf(-1.0 / alpha)
}

/// A point of the bedrock at `distance` from network node `anchor`, in the direction a
/// tributary leaves a passage: at an acute angle of 20–70° to the passage there (Horton's
/// junction angles), to either side and either way along it, in the bedding plane, rising or
/// falling by at most 30°.
fn draw_tributary(
    view: &SkeletonView,
    samples: &Samples,
    network: &NetworkBuilder,
    rng: &mut Random,
    anchor: usize,
    distance: f64,
) -> Option<DVec3> {
    let at = |i: u32| DVec3::from_array(samples.positions[network.samples[i as usize] as usize]);
    let centre = at(anchor as u32);
    let next = &network.adjacency[anchor];
    let tangent = match next.as_slice() {
        [] => DVec3::X,
        [one] => centre - at(*one),
        [a, b, ..] => at(*b) - at(*a),
    };
    let up = bedding_normal(view.geology, centre);
    let along = (tangent - up * tangent.dot(up)).normalize_or(up.any_orthonormal_vector());
    let side = up.cross(along);
    (0..TRIES).find_map(|_| {
        let turn = rng.range(20f64, 70.0).to_radians() * if rng.uniform() < 0.5 { -1.0 } else { 1.0 };
        let way = if rng.uniform() < 0.5 { -1.0 } else { 1.0 };
        let rise = rng.range(-30f64, 30.0).to_radians();
        let flat = (along * (way * turn.cos()) + side * turn.sin()) * rise.cos();
        let p = centre + (flat + up * rise.sin()) * distance;
        view.in_bedrock(p).then_some(p)
    })
}

fn nearest_sample(samples: &Samples, p: DVec3) -> usize {
    let d = |i: usize| DVec3::from_array(samples.positions[i]).distance_squared(p);
    (0..samples.len()).min_by(|&a, &b| d(a).total_cmp(&d(b))).expect("samples are never empty")
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn power_law_lengths_follow_their_tail() {
        let mut rng = Random::stream(1, "test", "power law");
        let (min, max, alpha) = (20.0, 400.0, 1.2);
        let lengths: Vec<f64> = (0..20_000).map(|_| power_law(&mut rng, min, max, alpha)).collect();
        assert!(lengths.iter().all(|l| (min..=max).contains(l)));
        let tail = |x: f64| (x.powf(-alpha) - max.powf(-alpha)) / (min.powf(-alpha) - max.powf(-alpha));
        for x in [30.0, 60.0, 150.0] {
            let share = lengths.iter().filter(|l| **l > x).count() as f64 / lengths.len() as f64;
            assert!((share - tail(x)).abs() < 0.01, "P(ℓ > {x}) = {share}, expected {}", tail(x));
        }
    }
}
