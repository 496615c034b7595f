//! The least cost from every sample to a spring: the phreatic A*'s heuristic when many legs
//! go to the same spring (`karstnsim.rs`, `cohesion_bound.rs`).
//!
//! The phreatic legs are most of the skeleton's time on a large scene (on the regional scene, its
//! legs together reach many times the samples there are: BENCHMARKS.md). Their heuristic bounds the
//! cost still to pay by the least cost per metre of any edge times the straight-line distance; the
//! cheapest edges of a set are rare (straight down through the vadose zone, along the water table),
//! so the bound is loose and each search explores a wide ellipsoid between its entry and the
//! spring. The exact least cost to the spring, T(v) = d(v, t), is the tightest bound there is, and
//! one Dijkstra over the reversed graph from the spring gives it for every sample at once: about
//! the cost of one or two phreatic legs, repaid when the spring drains many sinks (the regional
//! scene's springs drain 20 each; the peer scene's 4, and there it would not pay). It is computed
//! on the phase's costs before cohesion (the inherited conduits' factor included), which cohesion
//! only lowers: `cohesion_bound.rs` combines T with the network's discount so that the bound stays
//! admissible and consistent.
//!
//! T is computed where the spring is reachable and is +∞ elsewhere (those samples cannot reach
//! it at any cost: no bound is wrong there). Sums are taken from the spring outwards, so T(u) ≤
//! T(v) + c(u → v) holds for every edge in floating point too: each T(u) is the least of those
//! sums. The memory: the reversed rows (4 bytes per edge, freed once every spring is done) and
//! 8 bytes per sample per spring that pays.

use karst_costgraph::CostGraph;

use crate::route::search::{Direct, RadixHeap};

/// Candidate legs towards one spring in a phase from which its least costs are computed.
pub const LEGS_WORTH_THE_COSTS: usize = 10;

/// The cost graph's edges grouped by their target: the sources of the edges into node v are
/// `sources[offsets[v]..offsets[v + 1]]`, in increasing order.
pub struct InEdges {
    offsets: Vec<u32>,
    sources: Vec<u32>,
}

impl InEdges {
    pub fn of(graph: &CostGraph) -> Self {
        let (offsets, sources) = karst_costgraph::transpose(&graph.offsets, &graph.targets);
        InEdges { offsets, sources }
    }

    /// The positions of node v's in-edges in the reversed rows.
    fn into(&self, v: usize) -> std::ops::Range<usize> {
        self.offsets[v] as usize..self.offsets[v + 1] as usize
    }
}

/// T(v), the least cost from every sample v to `spring` under `costs` (+∞ where there is no
/// path): Dijkstra from the spring along the reversed edges, their costs laid out beside the
/// reversed rows first so that relaxing an in-edge reads the next number instead of the
/// source's row (a cache miss for its offsets, its targets, its costs). None when a cohesion
/// layer of `costs` changes some cost (a later phase's inherited conduits): those costs are not
/// the stored ones, and the heuristic then does without.
///
/// `reversed` is scratch space for those costs (4 bytes per edge), kept between springs.
pub fn costs_to(
    costs: &Direct,
    in_edges: &InEdges,
    spring: usize,
    reversed: &mut Vec<f32>,
) -> Option<Vec<f64>> {
    if costs.layers.iter().flatten().any(|layer| layer.factor != 1.0) {
        return None;
    }
    let graph = costs.graph;
    let stored = |u: usize| {
        let row = graph.row_costs(costs.set, u);
        move |place: usize| row[place]
    };
    reversed.resize(graph.edge_count(), 0.0);
    karst_costgraph::transpose_values(&graph.offsets, &graph.targets, &in_edges.offsets, stored, reversed);
    let mut least = vec![f64::INFINITY; graph.node_count()];
    let mut heap = RadixHeap::new();
    least[spring] = 0.0;
    heap.push(0.0f64.to_bits(), spring as u32);
    while let Some((key, v)) = heap.pop_entry() {
        let v = v as usize;
        // A node is pushed again only with a smaller cost (never raised: costs ≥ 0), so the
        // entry holding its least cost is the one to settle it and any other is stale. (No
        // settled flags: their reads were a cache miss per pop, a tenth of the time here.)
        let here = least[v];
        if key != here.to_bits() {
            continue;
        }
        for k in in_edges.into(v) {
            // A settled source has its least cost already, never above this (costs ≥ 0).
            let (u, through) = (in_edges.sources[k] as usize, here + f64::from(reversed[k]));
            if through < least[u] {
                least[u] = through;
                heap.push(through.to_bits(), u as u32);
            }
        }
    }
    Some(least)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::route::edge_set::EdgeSet;
    use crate::route::search::{Cohesive, EdgeCosts, dijkstra};
    use karst_scene::rng::Random;

    /// A random directed graph: each node joined to 6 others at random costs.
    fn random_graph(rng: &mut Random, n: usize) -> CostGraph {
        let lists = (0..n)
            .map(|u| {
                let mut row: Vec<(u32, f32)> = Vec::new();
                while row.len() < 6 {
                    let v = rng.index(n) as u32;
                    if v as usize != u && row.iter().all(|(t, _)| *t != v) {
                        row.push((v, rng.range(0.5, 4.0) as f32));
                    }
                }
                row
            })
            .collect();
        CostGraph::from_lists(lists)
    }

    #[test]
    fn the_least_costs_to_a_spring_are_each_samples_dijkstra_cost() {
        let mut rng = Random::stream(8, "test", "spring-distance");
        let graph = random_graph(&mut rng, 300);
        let mut inherited = EdgeSet::new(graph.edge_count());
        for e in 0..graph.edge_count() {
            if rng.range(0.0, 1.0) < 0.2 {
                inherited.insert(e);
            }
        }
        let costs = Cohesive { base: &graph, used: &inherited, factor: 1.0 };
        let in_edges = InEdges::of(&graph);
        let discounted = Cohesive { base: &graph, used: &inherited, factor: 0.5 };
        assert!(
            costs_to(&discounted.direct().expect("graph costs"), &in_edges, 0, &mut Vec::new()).is_none()
        );
        for spring in [0, 123, 299] {
            let least = costs_to(&costs.direct().expect("graph costs"), &in_edges, spring, &mut Vec::new())
                .expect("stored costs");
            for v in 0..graph.node_count() {
                let exact = dijkstra(&costs, v, &[spring]).cost(spring);
                assert!(
                    (least[v] - exact).abs() <= 1e-9 * exact,
                    "{v} → {spring}: {} against {exact}",
                    least[v]
                );
                // Consistent in floating point: no edge into v leads to a smaller sum.
                costs.for_each_out(v, &mut |_, t, c| assert!(least[v] <= least[t] + c, "{v} → {t}"));
            }
        }
    }
}
