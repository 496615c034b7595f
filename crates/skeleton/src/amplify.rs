//! Amplification (Paris et al. 2021 §5.2, KarstNSim §4.6): after the main network is drawn,
//! `skeleton.amplification_steps` times, `skeleton.amplification_points` new key points are
//! drawn uniformly in the bedrock of the network's bounding box and joined to the network by
//! least-cost paths:
//!
//! - a dead end (probability `skeleton.dead_end_fraction`) is joined once, to the cheapest
//!   network node;
//! - an interior point is joined twice: to the cheapest network node n₁, then to the cheapest
//!   network node farther than twice |p − n₁| from n₁, so that the second path reaches another
//!   part of the network and closes a loop (when no such node is reachable, the point stays a
//!   dead end).
//!
//! Each new point is snapped to its nearest sample, so it lies in the bedrock. Later steps
//! join the network grown by earlier steps. No route uses these branches: they are dry in the
//! flow stage.

use glam::DVec3;
use karst_costgraph::CostGraph;
use karst_geology::params::SkeletonMode;
use karst_geology::rng::Random;
use karst_geology::{KeyPointKind, Scene};
use karst_sampling::Samples;

use crate::assemble::NetworkBuilder;
use crate::ends::{End, sample_of};
use crate::error::SkeletonError;
use crate::search::dijkstra_to_set;

/// Tries to draw one point inside the bedrock before giving up on it.
const TRIES: usize = 64;

/// Joins the key points the mode did not route: dead ends once (both modes) and, in karstnsim
/// mode, waypoints twice, like amplification's dead ends and interior points. Errors name a
/// key point that cannot reach the network.
pub fn join_keypoints(
    scene: &Scene,
    samples: &Samples,
    graph: &CostGraph,
    network: &mut NetworkBuilder,
) -> Result<(), SkeletonError> {
    let waypoints_routed = scene.skeleton().mode == SkeletonMode::Gamma;
    for (index, k) in scene.keypoints().iter().enumerate() {
        let dead_end = match k.kind {
            KeyPointKind::DeadEnd => true,
            KeyPointKind::Waypoint if !waypoints_routed => false,
            _ => continue,
        };
        let end = End { row: index, keypoint: index, name: &k.name };
        let start = sample_of(samples, &end)?;
        if !join(samples, graph, network, start, dead_end) {
            return Err(SkeletonError::KeyPointOffNetwork { name: k.name.clone() });
        }
    }
    Ok(())
}

/// Adds the amplification branches to `network`.
pub fn amplify(scene: &Scene, samples: &Samples, graph: &CostGraph, network: &mut NetworkBuilder) {
    let p = scene.skeleton();
    let mut rng = Random::stream(scene.seed(), "skeleton", "amplification");
    for _ in 0..p.amplification_steps {
        let (lo, hi) = bounding_box(samples, network);
        for _ in 0..p.amplification_points {
            let dead_end = rng.uniform() < p.dead_end_fraction;
            let Some(point) = draw_in_bedrock(scene, &mut rng, lo, hi) else { continue };
            let start = nearest_sample(samples, point);
            join(samples, graph, network, start, dead_end);
        }
    }
}

/// Joins sample `start` to the network once (dead end) or twice (interior point); false when
/// it cannot reach the network.
fn join(
    samples: &Samples,
    graph: &CostGraph,
    network: &mut NetworkBuilder,
    start: usize,
    dead_end: bool,
) -> bool {
    let on_network = network_mask(samples, network);
    if on_network[start] {
        return true;
    }
    let (tree, reached) = dijkstra_to_set(graph, start, |v| on_network[v]);
    let Some(first) = reached else { return false };
    let path = tree.path(first).expect("reached");
    if !dead_end {
        let at = |v: usize| DVec3::from_array(samples.positions[v]);
        let far = 2.0 * at(start).distance(at(first));
        let (tree, second) =
            dijkstra_to_set(graph, start, |v| on_network[v] && at(v).distance(at(first)) > far);
        if let Some(second) = second {
            network.add_path(&tree.path(second).expect("reached"));
        }
    }
    network.add_path(&path);
    true
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

fn draw_in_bedrock(scene: &Scene, rng: &mut Random, lo: DVec3, hi: DVec3) -> Option<DVec3> {
    (0..TRIES).find_map(|_| {
        let p = DVec3::new(rng.range(lo.x, hi.x), rng.range(lo.y, hi.y), rng.range(lo.z, hi.z));
        scene.in_bedrock(p).then_some(p)
    })
}

fn nearest_sample(samples: &Samples, p: DVec3) -> usize {
    let d = |i: usize| DVec3::from_array(samples.positions[i]).distance_squared(p);
    (0..samples.len()).min_by(|&a, &b| d(a).total_cmp(&d(b))).expect("samples are never empty")
}
