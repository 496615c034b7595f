//! KarstNSim mode (Gouy et al. 2024, §1.4, §2.4–2.6, §4.5): every sink, in its iteration order,
//! is routed in two legs towards each spring it drains to:
//!
//! 1. vadose: the least-cost path from the sink to the spring's water table, i.e. to the
//!    cheapest sample at or below it (none when the sink is already phreatic);
//! 2. phreatic: the least-cost path (A*) from that point to the spring.
//!
//! Each spring routes on the cost set of its own water table (KarstNSim's C_WT differs per
//! water table); the caller supplies the cost set by water-table name.
//!
//! Cohesion: once a sink's conduits are chosen, their edges (both directions) are marked used;
//! later searches multiply the cost of used edges by P_red, `skeleton.cohesion_vadose` in the
//! vadose leg and `skeleton.cohesion_phreatic` in the phreatic leg, so later conduits are
//! attracted by earlier ones (Figure 6). With P_red = 1 every route is independent of the
//! order of the sinks. The legs towards the several springs of one sink are all computed on
//! the network as it stood before that sink.
//!
//! Polygenic karsts (§2.6): a scene may list `[[phases]]`, oldest first. Each phase routes every
//! sink to the springs active then (its connectivity restricted to them; a sink with none
//! sits the phase out), on costs where the edges of the earlier phases' conduits are multiplied
//! by the phase's `inherited_cost`, so the new network reuses the old where it helps. The
//! routes of the last phase are the network's present drainage; conduits only earlier phases
//! used are relict (dry).

use std::collections::{BTreeMap, HashMap};

use glam::DVec3;
use karst_costgraph::CostGraph;
use karst_geology::Surface;
use karst_sampling::Samples;
use karst_scene::KeyPointKind;
use rayon::prelude::*;

use crate::Route;
use crate::error::SkeletonError;
use crate::route::ahead::Ahead;
use crate::route::cohesion_bound::{CohesionBound, NetworkDistance};
use crate::route::edge_set::EdgeSet;
use crate::route::ends::{End, candidate_springs, chosen_springs, ends, sample_of, sinks_in_order};
use crate::route::search::{Cohesive, EdgeCosts, Tree, astar_to_set, min_cost_per_metre};
use crate::route::spring_distance::{InEdges, LEGS_WORTH_THE_COSTS, costs_to};
use crate::view::SkeletonView;

/// The cost set of a water table, by name.
pub type CostSets<'g> = dyn Fn(&str) -> &'g (dyn EdgeCosts + 'g) + 'g;

/// What one phase routes to, and on which inherited network.
pub struct PhaseSetup<'a> {
    /// The springs active in the phase.
    pub springs: Vec<End<'a>>,
    /// Edges used by the conduits of the earlier phases.
    pub inherited: EdgeSet,
    /// Cost factor of those edges.
    pub inherited_cost: f64,
    /// Sink weights during the phase, by name (others keep their own).
    pub weights: BTreeMap<String, f64>,
}

impl<'a> PhaseSetup<'a> {
    /// The only phase of a scene without `[[phases]]`: every spring, nothing inherited.
    pub fn single(view: &SkeletonView<'a>, graph: &CostGraph) -> Self {
        PhaseSetup {
            springs: ends(view, KeyPointKind::Spring),
            inherited: EdgeSet::new(graph.edge_count()),
            inherited_cost: 1.0,
            weights: BTreeMap::new(),
        }
    }
}

/// One sink-to-spring path: its samples, edge ids and cost.
struct Leg {
    path: Vec<usize>,
    edges: Vec<usize>,
    cost: f64,
}

/// The routes of one phase and the edges its conduits use.
pub struct PhaseRoutes {
    pub routes: Vec<(Route, Vec<usize>)>,
    pub used: EdgeSet,
}

/// Routes `sinks` (in this order) to their springs in `phase`; returns each route with its
/// sample path. `graph` gives the edge ids shared by every cost set.
pub fn route<'g>(
    view: &SkeletonView,
    samples: &Samples,
    graph: &CostGraph,
    cost_set: &CostSets<'g>,
    sinks: &[End],
    phase: &PhaseSetup,
) -> Result<PhaseRoutes, SkeletonError> {
    route_mapping(view, samples, (graph, cost_set), sinks, phase, LEGS_WORTH_THE_COSTS)
}

/// [`route`], computing the least costs to a spring (`spring_distance.rs`) for the springs with
/// at least `legs_worth` candidate legs. The routes are the same whatever `legs_worth` (the
/// heuristic only changes which samples the searches settle), unless two paths cost exactly
/// the same.
pub(crate) fn route_mapping<'g>(
    view: &SkeletonView,
    samples: &Samples,
    (graph, cost_set): (&CostGraph, &CostSets<'g>),
    sinks: &[End],
    phase: &PhaseSetup,
    legs_worth: usize,
) -> Result<PhaseRoutes, SkeletonError> {
    let mut worth = springs_worth_their_costs(view, samples, cost_set, (sinks, phase), legs_worth)?;
    if !spring_costs_fit(view, graph, worth.len()) {
        worth.clear();
    }
    Ahead::run(graph, |ahead| {
        std::thread::scope(|scope| {
            // The least costs to the springs are computed on a thread of their own, in the order
            // the sinks first need them, while the sinks are routed: a leg waits for its spring's
            // costs (it never runs without them), so the routes do not depend on which finishes
            // first. With one thread they are all computed first.
            let (send, costs_ready) = std::sync::mpsc::channel();
            let wanted: Vec<usize> = worth.iter().map(|w| w.row).collect();
            if rayon::current_num_threads() > 1 {
                scope.spawn(move || costs_to_springs(graph, phase, worth, &send));
            } else {
                costs_to_springs(graph, phase, worth, &send);
            }
            let mut to_springs = SpringCosts { wanted, ready: BTreeMap::new(), costs_ready };
            route_sinks(view, samples, (graph, cost_set), (sinks, phase), (&mut to_springs, ahead))
        })
    })
}

/// The least costs to the springs that have them (`spring_distance.rs`), as their thread
/// delivers them.
struct SpringCosts {
    /// The spring rows whose costs are computed.
    wanted: Vec<usize>,
    ready: BTreeMap<usize, Option<Vec<f64>>>,
    costs_ready: std::sync::mpsc::Receiver<(usize, Option<Vec<f64>>)>,
}

impl SpringCosts {
    /// Waits until the costs of spring `row` are ready, if they are computed.
    fn wait_for(&mut self, row: usize) {
        while self.wanted.contains(&row) && !self.ready.contains_key(&row) {
            let (done, costs) = self.costs_ready.recv().expect("the spring costs' thread sends every spring");
            self.ready.insert(done, costs);
        }
    }

    fn of(&self, row: usize) -> Option<&[f64]> {
        self.ready.get(&row).and_then(|c| c.as_deref())
    }
}

/// Routes `sinks` one after the other (the body of [`route_mapping`]).
fn route_sinks<'g>(
    view: &SkeletonView,
    samples: &Samples,
    (graph, cost_set): (&CostGraph, &CostSets<'g>),
    (sinks, phase): (&[End], &PhaseSetup),
    (to_springs, ahead): (&mut SpringCosts, Option<&Ahead>),
) -> Result<PhaseRoutes, SkeletonError> {
    let springs = &phase.springs;
    let mut used = EdgeSet::new(graph.edge_count());
    let mut per_metre: BTreeMap<String, f64> = BTreeMap::new();
    let mut routes = Vec::new();
    // The network's samples so far, for the phreatic searches' bound (cohesion_bound.rs).
    let mut network =
        (view.skeleton.cohesion_phreatic < 1.0).then(|| NetworkDistance::new(&samples.positions));
    for sink in sinks {
        let source = sample_of(samples, sink)?;
        // The legs towards every candidate spring depend only on the network before this sink:
        // they are searched in parallel, then chosen among in the candidates' order.
        let mut searches = Vec::new();
        for spring in candidate_springs(view, sink, springs) {
            let table = water_table_of(view, &spring);
            let base = cost_set(&table.name);
            let m = *per_metre
                .entry(table.name.clone())
                .or_insert_with(|| min_cost_per_metre(base, &samples.positions) * phase.inherited_cost);
            searches.push((spring.row, base, table, m, sample_of(samples, &spring)?));
            to_springs.wait_for(spring.row);
        }
        let ready = &*to_springs;
        let searches: Vec<_> = searches.into_iter().map(|s| (s, ready.of(s.0))).collect();
        let found: Vec<(usize, Option<Leg>)> = searches
            .into_par_iter()
            .map(|((row, base, table, m, target), to_spring)| {
                let costs = &Cohesive { base, used: &phase.inherited, factor: phase.inherited_cost };
                let known = Known { network: network.as_ref(), to_spring, ahead };
                (row, leg(view, samples, costs, &used, known, m, table, source, target))
            })
            .collect();
        let costs: BTreeMap<usize, f64> =
            found.iter().map(|(row, l)| (*row, l.as_ref().map_or(f64::INFINITY, |l| l.cost))).collect();
        let legs: BTreeMap<usize, Leg> = found.into_iter().filter_map(|(row, l)| Some((row, l?))).collect();
        let chosen = chosen_springs(view, sink, springs, &mut |spring| Ok(costs[&spring.row]))?;
        for spring in chosen {
            let leg = &legs[&spring.row];
            mark_used(graph, &leg.edges, &mut used);
            if !leg.edges.is_empty()
                && let Some(network) = &mut network
            {
                network.add(&leg.path);
            }
            let route = Route {
                sink: sink.name.to_string(),
                spring: spring.name.to_string(),
                weight: phase.weights.get(sink.name).copied().unwrap_or(view.keypoints[sink.keypoint].weight),
                nodes: Vec::new(),
                cost: leg.cost,
            };
            routes.push((route, leg.path.clone()));
        }
    }
    Ok(PhaseRoutes { routes, used })
}

/// A spring whose least costs are computed: its row, its cost set, its sample.
struct Mapped<'g> {
    row: usize,
    costs: &'g (dyn EdgeCosts + 'g),
    target: usize,
}

/// The springs of `phase` with at least `legs_worth` candidate legs among `sinks`, in the order
/// the sinks first need them.
fn springs_worth_their_costs<'g>(
    view: &SkeletonView,
    samples: &Samples,
    cost_set: &CostSets<'g>,
    (sinks, phase): (&[End], &PhaseSetup),
    legs_worth: usize,
) -> Result<Vec<Mapped<'g>>, SkeletonError> {
    let mut worth = Vec::new();
    for row in springs_with_legs(view, (sinks, phase), legs_worth) {
        let spring =
            phase.springs.iter().find(|s| s.row == row).expect("a candidate is a spring of the phase");
        let costs = cost_set(&water_table_of(view, spring).name);
        worth.push(Mapped { row, costs, target: sample_of(samples, spring)? });
    }
    Ok(worth)
}

/// The rows of the springs of `phase` with at least `legs_worth` candidate legs among `sinks`,
/// in the order the sinks first need them.
fn springs_with_legs(
    view: &SkeletonView,
    (sinks, phase): (&[End], &PhaseSetup),
    legs_worth: usize,
) -> Vec<usize> {
    let mut legs: Vec<(usize, usize)> = Vec::new();
    for sink in sinks {
        for spring in candidate_springs(view, sink, &phase.springs) {
            match legs.iter_mut().find(|(row, _)| *row == spring.row) {
                Some((_, n)) => *n += 1,
                None => legs.push((spring.row, 1)),
            }
        }
    }
    legs.into_iter().filter(|&(_, n)| n >= legs_worth).map(|(row, _)| row).collect()
}

/// Whether [`route`] computes the least costs to some spring of `phase` (`spring_distance.rs`),
/// which reads every edge of the spring's cost set.
pub fn maps_springs(view: &SkeletonView, graph: &CostGraph, phase: &PhaseSetup) -> bool {
    let springs = springs_with_legs(view, (&sinks_in_order(view), phase), LEGS_WORTH_THE_COSTS).len();
    phase.inherited_cost == 1.0 && springs > 0 && spring_costs_fit(view, graph, springs)
}

/// Whether the least costs to `springs` springs fit in the memory budget beside the cost graph:
/// they are a speed-up, so a run near its budget does without them rather than exceed it. They
/// take 4 bytes per edge for the reversed rows and 4 for one spring's reversed costs, 8 bytes
/// per sample per spring for T, and a search's 9 bytes per sample.
fn spring_costs_fit(view: &SkeletonView, graph: &CostGraph, springs: usize) -> bool {
    let nodes = graph.node_count() as f64;
    let extra = 8.0 * graph.edge_count() as f64 + nodes * (8.0 * springs as f64 + 9.0);
    // The cost graph, the samples (about 64 bytes each with their tags) and the searches'
    // per-sample arrays (about 100 bytes) are in memory already.
    let resident = graph.bytes_in_memory() as f64 + 164.0 * nodes;
    springs == 0 || resident + extra <= view.budget.bytes as f64
}

/// Computes T, the least cost from every sample to each spring of `worth` (`spring_distance.rs`),
/// on the phase's costs before cohesion, one spring after the other, and sends it by spring row
/// (None when those costs are not the stored ones). One spring at a time: side by side, each
/// held its reversed costs, which took the regional scene's skeleton over its memory budget.
fn costs_to_springs(
    graph: &CostGraph,
    phase: &PhaseSetup,
    worth: Vec<Mapped>,
    send: &std::sync::mpsc::Sender<(usize, Option<Vec<f64>>)>,
) {
    if worth.is_empty() {
        return;
    }
    let in_edges = InEdges::of(graph);
    let mut reversed = Vec::new();
    for Mapped { row, costs: base, target } in worth {
        let costs = Cohesive { base, used: &phase.inherited, factor: phase.inherited_cost };
        let least = costs.direct().and_then(|d| costs_to(&d, &in_edges, target, &mut reversed));
        if send.send((row, least)).is_err() {
            return; // The routing stopped (an error): nobody waits for the rest.
        }
    }
}

/// What a leg knows besides the costs: the phreatic leg's bound (`cohesion_bound.rs`), and the
/// helper costing rows ahead.
#[derive(Clone, Copy)]
struct Known<'a> {
    /// The network so far (None without cohesion).
    network: Option<&'a NetworkDistance<'a>>,
    /// The least costs to the leg's spring, when computed.
    to_spring: Option<&'a [f64]>,
    /// The helper that costs the rows the searches read next, if any.
    ahead: Option<&'a Ahead<'a>>,
}

fn water_table_of<'s>(view: &SkeletonView<'s>, spring: &End) -> &'s Surface {
    let name = view.keypoints[spring.keypoint].water_table.as_deref().unwrap_or_default();
    view.geology.water_table(name).expect("validation: every spring names a defined water table")
}

/// The vadose then phreatic path from `source` to `target`, or None when unreachable.
#[allow(clippy::too_many_arguments)]
fn leg(
    view: &SkeletonView,
    samples: &Samples,
    costs: &dyn EdgeCosts,
    used: &EdgeSet,
    known: Known,
    per_metre: f64,
    table: &Surface,
    source: usize,
    target: usize,
) -> Option<Leg> {
    let p = view.skeleton;
    let at = |v: usize| DVec3::from_array(samples.positions[v]);
    let phreatic = |v: usize| table.height_above(at(v)) <= 0.0;
    let vadose_costs = Cohesive { base: costs, used, factor: p.cohesion_vadose };
    // Every edge costs at least this per metre of its length, and the water table is at least
    // `depth_bound` away: A* towards it.
    let vadose_per_metre = per_metre * p.cohesion_vadose.min(1.0);
    let to_water_table = |v: usize| vadose_per_metre * depth_bound(table, at(v));
    let (vadose, reached) = astar_to_set((&vadose_costs, known.ahead), source, to_water_table, phreatic);
    let entry = reached?;
    let phreatic_costs = Cohesive { base: costs, used, factor: p.cohesion_phreatic };
    let bound = CohesionBound {
        positions: &samples.positions,
        per_metre,
        factor: p.cohesion_phreatic,
        network: known.network,
        target,
        to_spring: known.to_spring,
    };
    let (phreatic, _) =
        astar_to_set((&phreatic_costs, known.ahead), entry, bound.heuristic(), |v| v == target);
    joined((&vadose, entry), (&phreatic, target))
}

/// The vadose path to `entry` followed by the phreatic path from `entry` to `target`, without
/// the loop the two make when the phreatic path climbs back through nodes the vadose path came
/// down: it may, since a later phase's inherited conduits make the way back up the same shaft
/// cheap, and a route through a node twice would carry its water down and up one conduit. The
/// route leaves the vadose path at its first node the phreatic path also visits, there joining
/// the phreatic path's conduit: a simple path, never dearer than the two legs (a cycle of edges
/// of positive cost is dropped). Without a shared node it is the two legs end to end.
fn joined((vadose, entry): (&Tree, usize), (phreatic, target): (&Tree, usize)) -> Option<Leg> {
    let down = vadose.path(entry)?;
    let on = phreatic.path(target)?;
    let along: HashMap<usize, usize> = on.iter().enumerate().map(|(i, &v)| (v, i)).collect();
    // `entry` is the last node of `down` and the first of `on`: a shared node always exists.
    let (leave, join) = down
        .iter()
        .enumerate()
        .find_map(|(i, v)| along.get(v).map(|&j| (i, j)))
        .unwrap_or((down.len() - 1, 0));
    let mut path = down[..leave].to_vec();
    path.extend(&on[join..]);
    // Edge i of a path goes from its node i to its node i + 1.
    let mut edges = vadose.edges(entry)[..leave].to_vec();
    edges.extend(&phreatic.edges(target)[join..]);
    let cost = vadose.cost(down[leave]) + (phreatic.cost(target) - phreatic.cost(on[join]));
    Some(Leg { path, edges, cost })
}

/// A lower bound of the distance from `p` to the water table's phreatic side that changes by at
/// most the distance moved (so that the vadose A* heuristic is consistent): the height of `p`
/// above a plane along its normal; 0 for a TIN (whose distance costs a search of its
/// triangles: the vadose leg then runs as plain Dijkstra).
fn depth_bound(table: &Surface, p: DVec3) -> f64 {
    if table.mesh().is_some() { 0.0 } else { table.signed_distance(p).max(0.0) }
}

/// Marks `edges` and their reverse edges used.
pub fn mark_used(graph: &CostGraph, edges: &[usize], used: &mut EdgeSet) {
    for &e in edges {
        used.insert(e);
        let v = graph.targets[e] as usize;
        let u = graph.offsets.partition_point(|&o| o as usize <= e) - 1;
        let first = graph.offsets[v] as usize;
        if let Some(j) = graph.out_edges(v).position(|(t, _)| t == u) {
            used.insert(first + j);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::route::search::dijkstra;

    /// 0 (a sink) → 1 → 2 (the water table) down a shaft; from 2 the spring 4 is reached back up
    /// through 1 and along a cheap inherited conduit 1 → 3 → 4, or directly at a high price.
    fn shaft() -> CostGraph {
        CostGraph::from_lists(vec![
            vec![(1, 1.0)],
            vec![(2, 1.0), (3, 0.5)],
            vec![(1, 1.0), (4, 10.0)],
            vec![(4, 0.5)],
            vec![],
        ])
    }

    #[test]
    fn a_route_leaves_the_shaft_where_the_phreatic_path_climbs_back() {
        let graph = shaft();
        let (vadose, phreatic) = (dijkstra(&graph, 0, &[2]), dijkstra(&graph, 2, &[4]));
        assert_eq!(phreatic.path(4), Some(vec![2, 1, 3, 4]), "the case: up the shaft again");
        let leg = joined((&vadose, 2), (&phreatic, 4)).unwrap();
        assert_eq!(leg.path, vec![0, 1, 3, 4]);
        // Edge ids: 0 → 1 is 0, 1 → 3 is 2, 3 → 4 is 5.
        assert_eq!(leg.edges, vec![0, 2, 5]);
        assert_eq!(leg.cost, 2.0);
    }

    #[test]
    fn legs_without_a_shared_node_are_joined_end_to_end() {
        let graph = shaft();
        let (vadose, phreatic) = (dijkstra(&graph, 0, &[1]), dijkstra(&graph, 1, &[4]));
        let leg = joined((&vadose, 1), (&phreatic, 4)).unwrap();
        assert_eq!(leg.path, vec![0, 1, 3, 4]);
        assert_eq!(leg.edges, vec![0, 2, 5]);
        assert_eq!(leg.cost, vadose.cost(1) + phreatic.cost(4));
        assert!(joined((&vadose, 1), (&dijkstra(&graph, 4, &[0]), 0)).is_none(), "unreachable");
    }
}
