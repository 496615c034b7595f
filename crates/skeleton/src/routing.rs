//! The skeleton of a scene: the mode ([`karstnsim`] or [`gamma`]) draws the sample paths, the
//! [`NetworkBuilder`] turns them into the artifact. Shared here: the sinks in their iteration
//! order and the choice of the springs a sink drains to.
//!
//! Sinks are taken by increasing `order`; sinks of equal order are shuffled by the scene seed
//! (KarstNSim §1.4: "by default, the iteration order ... is randomized"). A sink drains to every
//! spring its connectivity row marks 1; when the row has no 1, to the cheapest of the springs
//! marked 2 (uncertain connectivity keeps the closest spring in the cost metric).

use karst_artifact::StageError;
use karst_costgraph::CostGraph;
use karst_geology::params::SkeletonMode;
use karst_geology::rng::Random;
use karst_geology::{KeyPointKind, Link, Scene};
use karst_sampling::Samples;

use crate::assemble::NetworkBuilder;
use crate::karstnsim::PhaseSetup;
use crate::search::{CostSetOf, EdgeCosts};
use crate::{Skeleton, amplify, gamma, karstnsim};

/// A sink or a spring: its row (column) in the connectivity matrix, its scene key point.
#[derive(Debug, Clone, Copy)]
pub struct End<'a> {
    pub row: usize,
    pub keypoint: usize,
    pub name: &'a str,
}

/// Builds the network of `scene` on the cost graph; each spring routes on the cost set of its
/// water table. Dead-end key points are
/// closed to the mode's paths and to amplification, then joined once.
pub fn build(scene: &Scene, samples: &Samples, full: &CostGraph) -> Result<Skeleton, StageError> {
    let mut network = NetworkBuilder::default();
    let closed = without_dead_ends(scene, samples, full);
    let graph = closed.as_ref().unwrap_or(full);
    let routes = match scene.skeleton.mode {
        SkeletonMode::Karstnsim => {
            // One cost set per spring's water table (KarstNSim §1.3): C_WT differs between them.
            let sets: Vec<CostSetOf> =
                (0..graph.cost_sets.len()).map(|set| CostSetOf { graph, set }).collect();
            let cost_set =
                |table: &str| -> &dyn EdgeCosts { &sets[graph.cost_set_of_water_table(table).unwrap_or(0)] };
            let sinks = sinks_in_order(scene);
            let mut inherited = vec![false; graph.edge_count()];
            let mut routes = Vec::new();
            for (index, mut setup) in phase_setups(scene, graph).into_iter().enumerate() {
                network.phase = index as u32;
                setup.inherited.clone_from(&inherited);
                let done = karstnsim::route(scene, samples, graph, &cost_set, &sinks, &setup)?;
                for (_, path) in &done.routes {
                    network.add_path(path);
                }
                for (old, new) in inherited.iter_mut().zip(&done.used) {
                    *old |= *new;
                }
                routes = done.routes;
            }
            routes
        }
        SkeletonMode::Gamma => gamma::network(scene, samples, graph, &mut network)?,
    };
    amplify::join_keypoints(scene, samples, full, &mut network)?;
    amplify::amplify(scene, samples, graph, &mut network);
    Ok(network.finish(scene, samples, routes))
}

/// The cost graph with the edges into or out of dead-end key points closed, so that no path but
/// their own passes through them; None when the scene has none.
fn without_dead_ends(scene: &Scene, samples: &Samples, graph: &CostGraph) -> Option<CostGraph> {
    let mut closed = vec![false; graph.node_count()];
    for (i, _) in scene.keypoints_of(KeyPointKind::DeadEnd) {
        if let Some(s) = samples.keypoint_sample(i) {
            closed[s] = true;
        }
    }
    closed.iter().any(|c| *c).then(|| {
        // Closed edges cost +∞ in every cost set: no search relaxes them, and edge ids (shared
        // with the per-edge cohesion state) stay those of the full graph.
        let mut open = graph.clone();
        for u in 0..graph.node_count() {
            for edge in graph.offsets[u] as usize..graph.offsets[u + 1] as usize {
                if closed[u] || closed[graph.targets[edge] as usize] {
                    for set in &mut open.cost_sets {
                        set.costs[edge] = f32::INFINITY;
                        set.min_cost_per_metre = None;
                    }
                }
            }
        }
        open
    })
}

/// The phases of the scene, oldest first (one with every spring when it lists none); their
/// inherited edges are filled in as the phases run.
fn phase_setups<'a>(scene: &'a Scene, graph: &CostGraph) -> Vec<PhaseSetup<'a>> {
    if scene.phases.is_empty() {
        return vec![PhaseSetup::single(scene, graph)];
    }
    let springs = ends(scene, KeyPointKind::Spring);
    scene
        .phases
        .iter()
        .map(|phase| PhaseSetup {
            springs: springs.iter().filter(|s| phase.springs.iter().any(|n| n == s.name)).copied().collect(),
            inherited: Vec::new(),
            inherited_cost: phase.inherited_cost,
            weights: phase.weights.clone(),
        })
        .collect()
}

/// The ends of `kind`, in scene order.
pub fn ends(scene: &Scene, kind: KeyPointKind) -> Vec<End<'_>> {
    scene
        .keypoints_of(kind)
        .enumerate()
        .map(|(row, (keypoint, k))| End { row, keypoint, name: &k.name })
        .collect()
}

/// The sinks by increasing `order`, equal orders shuffled by the seed.
pub fn sinks_in_order(scene: &Scene) -> Vec<End<'_>> {
    let mut rng = Random::stream(scene.seed, "skeleton", "sink order");
    let mut keyed: Vec<(i64, u64, End)> = ends(scene, KeyPointKind::Sink)
        .into_iter()
        .map(|s| (scene.keypoints[s.keypoint].order, (rng.uniform() * 2f64.powi(53)) as u64, s))
        .collect();
    keyed.sort_by_key(|(order, key, s)| (*order, *key, s.row));
    keyed.into_iter().map(|(_, _, s)| s).collect()
}

/// The springs `sink` drains to among `springs`, given the cost of reaching each allowed spring
/// (infinite when unreachable): every spring marked 1, else the cheapest marked 2; none when
/// no spring of `springs` is allowed. Errors name the sink and the spring it cannot reach.
pub fn chosen_springs<'a>(
    scene: &Scene,
    sink: &End,
    springs: &[End<'a>],
    cost_to: &mut dyn FnMut(&End<'a>) -> Result<f64, StageError>,
) -> Result<Vec<End<'a>>, StageError> {
    let allowed = allowed_springs(scene, sink, springs);
    let unreachable = |t: &End| {
        StageError::input(format!(
            "sink \"{}\" cannot reach spring \"{}\" through the cost graph (raise costgraph.k or max_edge_length)",
            sink.name, t.name
        ))
    };
    if allowed.is_empty() {
        return Ok(Vec::new());
    }
    let connected: Vec<End> =
        allowed.iter().filter(|(_, l)| *l == Link::Connected).map(|(t, _)| *t).collect();
    if !connected.is_empty() {
        for t in &connected {
            if !cost_to(t)?.is_finite() {
                return Err(unreachable(t));
            }
        }
        return Ok(connected);
    }
    let mut best: Option<(f64, End)> = None;
    for (t, _) in &allowed {
        let cost = cost_to(t)?;
        if cost.is_finite() && best.is_none_or(|(b, _)| cost < b) {
            best = Some((cost, *t));
        }
    }
    match best {
        Some((_, t)) => Ok(vec![t]),
        None => Err(unreachable(&allowed[0].0)),
    }
}

/// The springs [`chosen_springs`] asks the cost of, in the order it asks: those the sink's
/// connectivity row marks 1, else those it marks 2.
pub fn candidate_springs<'a>(scene: &Scene, sink: &End, springs: &[End<'a>]) -> Vec<End<'a>> {
    let allowed = allowed_springs(scene, sink, springs);
    let connected: Vec<End> =
        allowed.iter().filter(|(_, l)| *l == Link::Connected).map(|(t, _)| *t).collect();
    if connected.is_empty() { allowed.into_iter().map(|(t, _)| t).collect() } else { connected }
}

/// The springs the sink's connectivity row does not forbid, with their link.
fn allowed_springs<'a>(scene: &Scene, sink: &End, springs: &[End<'a>]) -> Vec<(End<'a>, Link)> {
    springs.iter().map(|t| (*t, scene.link(sink.row, t.row))).filter(|(_, l)| *l != Link::None).collect()
}

/// The sample of a key point, or an error naming it.
pub fn sample_of(samples: &Samples, end: &End) -> Result<usize, StageError> {
    samples.keypoint_sample(end.keypoint).ok_or_else(|| {
        StageError::input(format!(
            "key point \"{}\" is not in samples.bin (the scene changed since sampling: rerun `cargo xtask run --from sampling`)",
            end.name
        ))
    })
}
