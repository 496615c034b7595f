//! The skeleton of a scene, the algorithm's entry: the mode ([`karstnsim`] or [`gamma`]) draws
//! the sample paths on the cost graph, the key points it did not route are joined, the
//! network is amplified, and the [`NetworkBuilder`] turns the paths into the artifact.

use karst_costgraph::{CostGraph, Costing};
use karst_sampling::Samples;
use karst_scene::params::SkeletonMode;
use karst_scene::{KeyPointKind, keypoints_of};

use crate::defaults;
use crate::error::SkeletonError;
use crate::modes::karstnsim::PhaseSetup;
use crate::modes::{amplify, gamma, karstnsim};
use crate::network::assemble::NetworkBuilder;
use crate::payload::{Route, Skeleton};
use crate::route::edge_set::EdgeSet;
use crate::route::ends::{ends, sinks_in_order};
use crate::route::search::{CostSetOf, EdgeCosts};
use crate::view::SkeletonView;

/// Builds the network of `scene` on the cost graph; each spring routes on the cost set of its
/// water table. What `[skeleton]` leaves out of the tributaries and meanders is derived from the
/// scene ([`defaults`]), the tributary count once the routes are known. Dead-end key points are
/// closed to the mode's paths and to amplification, then joined once.
pub fn build(view: &SkeletonView, samples: &Samples, full: &CostGraph) -> Result<Skeleton, SkeletonError> {
    if full.node_count() != samples.len() {
        return Err(SkeletonError::GraphOfOtherSamples { nodes: full.node_count(), samples: samples.len() });
    }
    full.cost_from(&view.costs(), &samples.positions, costing(view, full))?;
    let mut resolved = defaults::resolve(view);
    let mut network = NetworkBuilder::default();
    let closed = without_dead_ends(view, samples, full);
    let graph = closed.as_ref().unwrap_or(full);
    let routes = mode_routes(view, samples, graph, &mut network)?;
    resolved.count(view, samples, &network);
    let view = &SkeletonView { skeleton: &resolved.params, ..*view };
    amplify::join_keypoints(view, samples, full, &mut network)?;
    amplify::amplify(view, samples, graph, &mut network);
    let mut skeleton = network.finish(view, samples, routes);
    skeleton.derived = resolved.derived;
    Ok(skeleton)
}

/// The least-cost paths of the scene's mode alone (no other key point joined, no amplification,
/// no conduits): what the skeleton budgets of `cargo xtask bench` time. Returns the number of
/// routes.
pub fn mode_paths(view: &SkeletonView, samples: &Samples, graph: &CostGraph) -> Result<usize, SkeletonError> {
    graph.cost_from(&view.costs(), &samples.positions, costing(view, graph))?;
    mode_routes(view, samples, graph, &mut NetworkBuilder::default()).map(|routes| routes.len())
}

/// The routes of the scene's mode, their paths added to `network`: KarstNSim's routing of every
/// sink, phase after phase, or the γ-skeleton of the key points.
fn mode_routes(
    view: &SkeletonView,
    samples: &Samples,
    graph: &CostGraph,
    network: &mut NetworkBuilder,
) -> Result<Vec<(Route, Vec<usize>)>, SkeletonError> {
    match view.skeleton.mode {
        SkeletonMode::Karstnsim => {
            // One cost set per spring's water table (KarstNSim §1.3): C_WT differs between them.
            let sets: Vec<CostSetOf> =
                (0..graph.cost_sets.len()).map(|set| CostSetOf { graph, set }).collect();
            let cost_set =
                |table: &str| -> &dyn EdgeCosts { &sets[graph.cost_set_of_water_table(table).unwrap_or(0)] };
            let sinks = sinks_in_order(view);
            let mut inherited = EdgeSet::new(graph.edge_count());
            let mut routes = Vec::new();
            for (index, mut setup) in phase_setups(view, graph).into_iter().enumerate() {
                network.phase = index as u32;
                setup.inherited.clone_from(&inherited);
                let done = karstnsim::route(view, samples, graph, &cost_set, &sinks, &setup)?;
                for (_, path) in &done.routes {
                    network.add_path(path);
                }
                inherited.union_with(&done.used);
                routes = done.routes;
            }
            Ok(routes)
        }
        SkeletonMode::Gamma => gamma::network(view, samples, graph, network),
    }
}

/// The cost graph with the edges into or out of dead-end key points closed, so that no path but
/// their own passes through them; None when the scene has none.
fn without_dead_ends(view: &SkeletonView, samples: &Samples, graph: &CostGraph) -> Option<CostGraph> {
    let mut closed = vec![false; graph.node_count()];
    for (i, _) in keypoints_of(view.keypoints, KeyPointKind::DeadEnd) {
        if let Some(s) = samples.keypoint_sample(i) {
            closed[s] = true;
        }
    }
    closed.iter().any(|c| *c).then(|| {
        // Closed edges cost +∞ in every cost set: no search relaxes them, and edge ids (shared
        // with the per-edge cohesion state) stay those of the full graph.
        let mut open = graph.clone();
        for u in 0..graph.node_count() {
            let first = graph.offsets[u] as usize;
            for edge in first..graph.offsets[u + 1] as usize {
                if closed[u] || closed[graph.targets[edge] as usize] {
                    for set in 0..open.cost_sets.len() {
                        // The least cost per metre stays a lower bound of the open edges'.
                        open.row_costs_mut(set, u)[edge - first] = f32::INFINITY;
                    }
                }
            }
        }
        open
    })
}

/// How the cost graph's rows are costed: all at once, in parallel, when some phase computes the
/// least costs to a spring (which reads every edge of its cost set: `spring_distance.rs`), else
/// each when a search first reads it.
fn costing(view: &SkeletonView, graph: &CostGraph) -> Costing {
    let whole = view.skeleton.mode == SkeletonMode::Karstnsim
        && phase_setups(view, graph).iter().any(|phase| karstnsim::maps_springs(view, graph, phase));
    if whole { Costing::Every } else { Costing::OnDemand }
}

/// The phases of the scene, oldest first (one with every spring when it lists none); their
/// inherited edges are filled in as the phases run.
fn phase_setups<'a>(view: &SkeletonView<'a>, graph: &CostGraph) -> Vec<PhaseSetup<'a>> {
    if view.phases.is_empty() {
        return vec![PhaseSetup::single(view, graph)];
    }
    let springs = ends(view, KeyPointKind::Spring);
    view.phases
        .iter()
        .map(|phase| PhaseSetup {
            springs: springs.iter().filter(|s| phase.springs.iter().any(|n| n == s.name)).copied().collect(),
            inherited: EdgeSet::default(),
            inherited_cost: phase.inherited_cost,
            weights: phase.weights.clone(),
        })
        .collect()
}
