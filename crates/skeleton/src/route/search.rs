//! Least-cost paths on the cost graph: Dijkstra for one source and many targets, A* for one
//! pair (Paris et al. 2021 §5.1, KarstNSim §1.4).
//!
//! Both run the same loop: A* is Dijkstra ordered by cost + heuristic. The heuristic is the
//! straight-line distance to the target times the smallest cost per metre of any edge of the
//! graph ([`min_cost_per_metre`]), which never overestimates the remaining cost (admissible)
//! and satisfies the triangle inequality along every edge (consistent), so a node is final when
//! it is settled. Searches on costs with cohesion take a heuristic of their own
//! ([`astar_to_set`]; the KarstNSim phreatic leg's is in `cohesion_bound.rs`). A path's cost is
//! the cost accumulated at its target, not a sum over the intermediate running costs.
//!
//! The graph is read through [`EdgeCosts`], so that a stage can route on another cost set over
//! the same edges (KarstNSim's per-water-table costs C_WT) or scale the costs of the edges the
//! network already uses (cohesion, [`Cohesive`]).
//!
//! The priority queue is a radix heap over the bits of the (non-negative) f64 keys, which order
//! like the floats: Dijkstra's keys never decrease, so a push only ever lands in the bucket of
//! its highest bit differing from the last key popped, and a pop redistributes one bucket.
//! That is about twice as fast as a binary heap here. Keys a rounding error below the last one
//! (A*'s heuristic) are raised to it. Equal keys pop in a fixed order: results are
//! deterministic.
//!
//! The per-node arrays of a search (costs, predecessors, settled flags) are kept per thread
//! when its tree is dropped, reset only where the search reached, for the next search: a
//! search costs what it explores, not the graph's size.

use glam::DVec3;
use karst_costgraph::CostGraph;
use rayon::prelude::*;

use crate::route::edge_set::EdgeSet;

use crate::route::ahead::{Ahead, HINT_EVERY, HINTED};

/// No predecessor.
const NONE: u32 = u32::MAX;

/// Directed, positive edge costs over a fixed set of edges. Edge ids index the edges of the
/// cost graph (its compressed rows), whatever the cost set, so that per-edge state such as
/// "already used by a conduit" is shared between cost sets.
pub trait EdgeCosts: Sync {
    fn node_count(&self) -> usize;
    /// Calls `f(edge id, target node, cost)` for every out-edge of `node`.
    fn for_each_out(&self, node: usize, f: &mut dyn FnMut(usize, usize, f64));
    /// The cost graph's rows, one of its cost sets and the cohesion layers on it, when the
    /// costs are these: searches then read them directly instead of through a callback per
    /// edge (several times faster: BENCHMARKS.md).
    fn direct(&self) -> Option<Direct<'_>> {
        None
    }
    /// The least cost per metre of the edges, when the cost graph recorded it for these costs.
    fn recorded_min_cost_per_metre(&self) -> Option<f64> {
        None
    }
}

/// Costs a search reads straight from the cost graph: edge e costs its cost in cost set `set`,
/// times the factor of every cohesion layer that marks e, the layers applied in order (as
/// nested [`Cohesive`]s do, so the products are the same bits).
#[derive(Clone, Copy)]
pub struct Direct<'a> {
    pub graph: &'a CostGraph,
    pub set: usize,
    pub layers: [Option<Layer<'a>>; 2],
}

/// A cohesion layer: the edges in `used` cost `factor` times more (P_red < 1: less).
#[derive(Clone, Copy)]
pub struct Layer<'a> {
    pub used: &'a EdgeSet,
    pub factor: f64,
}

impl Layer<'_> {
    #[inline]
    fn apply(&self, edge: usize, cost: f64) -> f64 {
        if self.used.contains(edge) { cost * self.factor } else { cost }
    }
}

impl<'a> Direct<'a> {
    fn plain(graph: &'a CostGraph, set: usize) -> Self {
        Direct { graph, set, layers: [None, None] }
    }

    /// Calls `f(edge, target, cost)` for every out-edge of `node`, with one loop per number of
    /// layers so that the plain loop tests nothing per edge.
    #[inline]
    fn for_each_out(&self, node: usize, mut f: impl FnMut(usize, usize, f64)) {
        let g = self.graph;
        let (first, last) = (g.offsets[node] as usize, g.offsets[node + 1] as usize);
        let edges = (first..last).zip(g.targets[first..last].iter().zip(g.row_costs(self.set, node)));
        match self.layers {
            [None, _] => edges.for_each(|(e, (&t, &c))| f(e, t as usize, f64::from(c))),
            [Some(a), None] => edges.for_each(|(e, (&t, &c))| f(e, t as usize, a.apply(e, f64::from(c)))),
            [Some(a), Some(b)] => {
                edges.for_each(|(e, (&t, &c))| f(e, t as usize, b.apply(e, a.apply(e, f64::from(c)))))
            }
        }
    }
}

impl EdgeCosts for CostGraph {
    fn node_count(&self) -> usize {
        CostGraph::node_count(self)
    }

    fn for_each_out(&self, node: usize, f: &mut dyn FnMut(usize, usize, f64)) {
        CostSetOf { graph: self, set: 0 }.for_each_out(node, f)
    }

    fn direct(&self) -> Option<Direct<'_>> {
        Some(Direct::plain(self, 0))
    }

    fn recorded_min_cost_per_metre(&self) -> Option<f64> {
        self.cost_sets[0].min_cost_per_metre
    }
}

/// One cost set of the cost graph (KarstNSim: the costs under one spring's water table).
pub struct CostSetOf<'a> {
    pub graph: &'a CostGraph,
    pub set: usize,
}

impl EdgeCosts for CostSetOf<'_> {
    fn node_count(&self) -> usize {
        self.graph.node_count()
    }

    fn for_each_out(&self, node: usize, f: &mut dyn FnMut(usize, usize, f64)) {
        let first = self.graph.offsets[node] as usize;
        for (j, (target, cost)) in self.graph.out_edges_in(self.set, node).enumerate() {
            f(first + j, target, f64::from(cost));
        }
    }

    fn direct(&self) -> Option<Direct<'_>> {
        Some(Direct::plain(self.graph, self.set))
    }

    fn recorded_min_cost_per_metre(&self) -> Option<f64> {
        self.graph.cost_sets[self.set].min_cost_per_metre
    }
}

/// A cost set whose edges already used by the network cost `factor` times less (KarstNSim's
/// cohesion P_red, §1.4 and §4.5): `used` holds them.
pub struct Cohesive<'a> {
    pub base: &'a dyn EdgeCosts,
    pub used: &'a EdgeSet,
    pub factor: f64,
}

impl EdgeCosts for Cohesive<'_> {
    fn node_count(&self) -> usize {
        self.base.node_count()
    }

    fn for_each_out(&self, node: usize, f: &mut dyn FnMut(usize, usize, f64)) {
        self.base.for_each_out(node, &mut |e, t, c| {
            f(e, t, if self.used.contains(e) { c * self.factor } else { c })
        });
    }

    fn direct(&self) -> Option<Direct<'_>> {
        let mut direct = self.base.direct()?;
        let free = direct.layers.iter_mut().find(|l| l.is_none())?;
        *free = Some(Layer { used: self.used, factor: self.factor });
        Some(direct)
    }
}

/// Cohesion by zone (gamma mode): used edges out of a phreatic node cost `factors[1]` times
/// their cost, used edges out of a vadose node `factors[0]` times.
pub struct ZonedCohesive<'a> {
    pub base: &'a dyn EdgeCosts,
    pub used: &'a EdgeSet,
    pub phreatic: &'a [bool],
    pub factors: [f64; 2],
}

impl EdgeCosts for ZonedCohesive<'_> {
    fn node_count(&self) -> usize {
        self.base.node_count()
    }

    fn for_each_out(&self, node: usize, f: &mut dyn FnMut(usize, usize, f64)) {
        let factor = self.factors[usize::from(self.phreatic[node])];
        self.base
            .for_each_out(node, &mut |e, t, c| f(e, t, if self.used.contains(e) { c * factor } else { c }));
    }
}

/// A cost set in which the edges into `blocked` nodes do not exist: searches go around them.
pub struct Blocked<'a> {
    pub base: &'a dyn EdgeCosts,
    pub blocked: &'a [bool],
}

impl EdgeCosts for Blocked<'_> {
    fn node_count(&self) -> usize {
        self.base.node_count()
    }

    fn for_each_out(&self, node: usize, f: &mut dyn FnMut(usize, usize, f64)) {
        self.base.for_each_out(node, &mut |e, t, c| {
            if !self.blocked[t] {
                f(e, t, c)
            }
        });
    }
}

/// The smallest cost per metre of any edge between distinct positions: the factor of the A*
/// heuristic. Zero when the graph has no such edge (the heuristic then vanishes).
/// The cost graph's record when it has one, else every edge is measured, the nodes in
/// parallel (a minimum is the same in any order).
pub fn min_cost_per_metre(graph: &dyn EdgeCosts, positions: &[[f64; 3]]) -> f64 {
    if let Some(least) = graph.recorded_min_cost_per_metre() {
        return least;
    }
    let direct = graph.direct();
    let least = (0..graph.node_count())
        .into_par_iter()
        .with_min_len(1024)
        .map(|u| {
            let pu = DVec3::from_array(positions[u]);
            let mut least = f64::INFINITY;
            let mut edge = |_, v: usize, c: f64| {
                let length = pu.distance(DVec3::from_array(positions[v]));
                if length > 0.0 {
                    least = least.min(c / length);
                }
            };
            match &direct {
                Some(d) => d.for_each_out(u, edge),
                None => graph.for_each_out(u, &mut edge),
            }
            least
        })
        .reduce(|| f64::INFINITY, f64::min);
    if least.is_finite() { least } else { 0.0 }
}

/// A shortest-path tree grown from one source, possibly partial (the search stops early).
pub struct Tree {
    /// Per node: the cost so far, the predecessor and the edge from it, side by side so that a
    /// relaxation touches one cache line.
    nodes: Vec<Reached>,
    /// The nodes reached, so that dropping the tree resets only them.
    reached: Vec<u32>,
}

#[derive(Clone, Copy)]
struct Reached {
    cost: f64,
    predecessor: u32,
    via: u32,
}

const UNREACHED: Reached = Reached { cost: f64::INFINITY, predecessor: NONE, via: NONE };

/// Per-node arrays of finished searches, reset, kept for the next search on the same thread:
/// allocating and filling them for every search (17 bytes per sample, for each of the regional
/// scene's searches) was most of the skeleton's system time (BENCHMARKS.md).
struct Spare {
    trees: Vec<Vec<Reached>>,
    settled: Vec<Vec<bool>>,
}

/// Spares kept per thread (a leg's vadose tree is alive while its phreatic search runs).
const SPARES: usize = 2;

thread_local! {
    static SPARE: std::cell::RefCell<Spare> =
        const { std::cell::RefCell::new(Spare { trees: Vec::new(), settled: Vec::new() }) };
}

/// A spare array of `n` entries, all `fresh`, or a new one.
fn spare<T: Clone>(pick: impl FnOnce(&mut Spare) -> &mut Vec<Vec<T>>, n: usize, fresh: T) -> Vec<T> {
    SPARE
        .with_borrow_mut(|spare| {
            let kept = pick(spare);
            kept.retain(|v| v.len() == n);
            kept.pop()
        })
        .unwrap_or_else(|| vec![fresh; n])
}

/// Gives `array` back for another search (its entries already reset).
fn keep<T>(pick: impl FnOnce(&mut Spare) -> &mut Vec<Vec<T>>, array: Vec<T>) {
    SPARE.with_borrow_mut(|spare| {
        let kept = pick(spare);
        if kept.len() < SPARES {
            kept.push(array);
        }
    });
}

impl Drop for Tree {
    fn drop(&mut self) {
        for &v in &self.reached {
            self.nodes[v as usize] = UNREACHED;
        }
        keep(|s| &mut s.trees, std::mem::take(&mut self.nodes));
    }
}

impl Tree {
    /// Cost of the least-cost path to `target`; infinite when it was not reached.
    pub fn cost(&self, target: usize) -> f64 {
        self.nodes[target].cost
    }

    /// The path source → target as node indices, or None when it was not reached.
    pub fn path(&self, target: usize) -> Option<Vec<usize>> {
        self.cost(target).is_finite().then(|| {
            let mut path = vec![target];
            let mut at = target;
            while self.nodes[at].predecessor != NONE {
                at = self.nodes[at].predecessor as usize;
                path.push(at);
            }
            path.reverse();
            path
        })
    }

    /// The edge ids of the path source → target (empty when not reached or target = source).
    pub fn edges(&self, target: usize) -> Vec<usize> {
        let mut edges = Vec::new();
        if !self.cost(target).is_finite() {
            return edges;
        }
        let mut at = target;
        while self.nodes[at].predecessor != NONE {
            edges.push(self.nodes[at].via as usize);
            at = self.nodes[at].predecessor as usize;
        }
        edges.reverse();
        edges
    }
}

/// Dijkstra from `source`, settling nodes by increasing cost until every node of `targets` is
/// settled (or everything reachable is).
pub fn dijkstra(graph: &dyn EdgeCosts, source: usize, targets: &[usize]) -> Tree {
    let mut remaining = targets.len();
    grow(
        (graph, None),
        source,
        |_| 0.0,
        |u| {
            if targets.contains(&u) {
                remaining -= 1;
            }
            remaining == 0
        },
    )
}

/// Dijkstra from `source` until the first node for which `is_target` holds is settled: the
/// cheapest member of a target set. Returns the tree and that node, if reachable.
pub fn dijkstra_to_set(
    graph: &dyn EdgeCosts,
    source: usize,
    is_target: impl Fn(usize) -> bool,
) -> (Tree, Option<usize>) {
    astar_to_set((graph, None), source, |_| 0.0, is_target)
}

/// A* from `source` to the cheapest node for which `is_target` holds. `heuristic` must be a
/// consistent lower bound of the cost to the set (0 on its members, and never dropping by
/// more than an edge's cost along it): the first member settled is then the cheapest, as with
/// [`dijkstra_to_set`], after settling fewer nodes. With `ahead`, a helper costs the rows the
/// search reads next.
pub fn astar_to_set(
    graph: (&dyn EdgeCosts, Option<&Ahead>),
    source: usize,
    heuristic: impl Fn(usize) -> f64,
    is_target: impl Fn(usize) -> bool,
) -> (Tree, Option<usize>) {
    let mut reached = None;
    let tree = grow(graph, source, heuristic, |u| {
        let hit = is_target(u);
        if hit {
            reached = Some(u);
        }
        hit
    });
    (tree, reached)
}

/// A* from `source` to `target` with the straight-line heuristic `per_metre` × distance
/// (`per_metre` must not exceed [`min_cost_per_metre`] of `graph`).
pub fn astar(
    graph: &dyn EdgeCosts,
    positions: &[[f64; 3]],
    per_metre: f64,
    source: usize,
    target: usize,
) -> Tree {
    let goal = DVec3::from_array(positions[target]);
    let heuristic = |v: usize| DVec3::from_array(positions[v]).distance(goal) * per_metre;
    grow((graph, None), source, heuristic, |u| u == target)
}

/// The common loop: nodes leave the heap by cost + heuristic; `settle(u)` returns true to stop.
/// With `ahead` serving the graph's rows, the nodes of least key are hinted to it every
/// [`HINT_EVERY`] settled nodes.
fn grow(
    (graph, ahead): (&dyn EdgeCosts, Option<&Ahead>),
    source: usize,
    heuristic: impl Fn(usize) -> f64,
    mut settle: impl FnMut(usize) -> bool,
) -> Tree {
    let n = graph.node_count();
    let mut tree = Tree { nodes: spare(|s| &mut s.trees, n, UNREACHED), reached: vec![source as u32] };
    let mut settled = spare(|s| &mut s.settled, n, false);
    let mut heap = RadixHeap::new();
    let direct = graph.direct();
    let ahead = ahead.filter(|a| direct.as_ref().is_some_and(|d| a.serves(d.graph)));
    let (mut hint, mut until_hint) = (Vec::new(), HINT_EVERY);
    tree.nodes[source].cost = 0.0;
    heap.push(heuristic(source).to_bits(), source as u32);
    while let Some(node) = heap.pop() {
        let u = node as usize;
        if settled[u] {
            continue;
        }
        settled[u] = true;
        if settle(u) {
            break;
        }
        if let Some(ahead) = ahead {
            until_hint -= 1;
            if until_hint == 0 {
                until_hint = HINT_EVERY;
                heap.lowest(HINTED, |v| !settled[v as usize], &mut hint);
                ahead.hint(&mut hint);
            }
        }
        let here = tree.nodes[u].cost;
        let mut relax = |edge: usize, v: usize, c: f64| {
            let through = here + c;
            let reached = &mut tree.nodes[v];
            if through < reached.cost {
                if reached.cost == f64::INFINITY {
                    tree.reached.push(v as u32);
                }
                *reached = Reached { cost: through, predecessor: node, via: edge as u32 };
                heap.push((through + heuristic(v)).to_bits(), v as u32);
            }
        };
        match &direct {
            Some(d) => d.for_each_out(u, relax),
            None => graph.for_each_out(u, &mut relax),
        }
    }
    if let Some(ahead) = ahead {
        ahead.forget();
    }
    // Only reached nodes are ever settled.
    for &v in &tree.reached {
        settled[v as usize] = false;
    }
    keep(|s| &mut s.settled, settled);
    tree
}

/// A monotone radix heap of (key, node): pops never return a key below the last one popped.
pub(crate) struct RadixHeap {
    last: u64,
    len: usize,
    buckets: [Vec<(u64, u32)>; 65],
}

impl RadixHeap {
    pub(crate) fn new() -> Self {
        RadixHeap { last: 0, len: 0, buckets: std::array::from_fn(|_| Vec::new()) }
    }

    fn bucket(&self, key: u64) -> usize {
        (64 - (key ^ self.last).leading_zeros()) as usize
    }

    pub(crate) fn push(&mut self, key: u64, node: u32) {
        let key = key.max(self.last);
        let b = self.bucket(key);
        self.buckets[b].push((key, node));
        self.len += 1;
    }

    /// Up to `n` nodes for which `wanted` holds among the entries of least key, into `out`, at
    /// the buckets' grain: the buckets in order (every key of a bucket is below every key of
    /// the next), in any order within one. Looks at no more than 4n entries, however many of
    /// them are unwanted.
    pub(crate) fn lowest(&self, n: usize, wanted: impl Fn(u32) -> bool, out: &mut Vec<u32>) {
        let entries = self.buckets.iter().flat_map(|bucket| bucket.iter().rev());
        out.extend(entries.take(4 * n).map(|&(_, node)| node).filter(|&node| wanted(node)).take(n));
    }

    pub(crate) fn pop(&mut self) -> Option<u32> {
        self.pop_entry().map(|(_, node)| node)
    }

    /// [`RadixHeap::pop`] with the key the node was pushed with (raised to the last key popped).
    pub(crate) fn pop_entry(&mut self) -> Option<(u64, u32)> {
        if self.len == 0 {
            return None;
        }
        if self.buckets[0].is_empty() {
            let i = (1..65).find(|&i| !self.buckets[i].is_empty()).expect("len > 0");
            let mut items = std::mem::take(&mut self.buckets[i]);
            self.last = items.iter().map(|(k, _)| *k).min().expect("non-empty bucket");
            for &(key, node) in &items {
                let b = self.bucket(key);
                self.buckets[b].push((key, node));
            }
            // Every item moved to a lower bucket: give the emptied one its allocation back.
            items.clear();
            self.buckets[i] = items;
        }
        self.len -= 1;
        self.buckets[0].pop()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn line_graph() -> (CostGraph, Vec<[f64; 3]>) {
        // 0 → 1 → 3 costs 2; 0 → 3 direct costs 5; 0 → 2 → 3 costs 3.
        let graph = CostGraph::from_lists(vec![
            vec![(1, 1.0), (2, 1.0), (3, 5.0)],
            vec![(3, 1.0)],
            vec![(3, 2.0)],
            vec![],
        ]);
        let positions = vec![[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [1.0, 1.0, 0.0]];
        (graph, positions)
    }

    #[test]
    fn the_radix_heap_pops_in_key_order() {
        let mut rng = karst_scene::rng::Random::stream(2, "test", "radix");
        let mut heap = RadixHeap::new();
        let mut keys: Vec<f64> = (0..500).map(|_| rng.range(0.0, 1e4)).collect();
        for (i, k) in keys.iter().enumerate() {
            heap.push(k.to_bits(), i as u32);
        }
        let mut popped = Vec::new();
        while let Some(i) = heap.pop() {
            popped.push(keys[i as usize]);
        }
        keys.sort_by(f64::total_cmp);
        assert_eq!(popped, keys);
    }

    #[test]
    fn the_lowest_entries_are_the_least_keys_wanted() {
        let mut heap = RadixHeap::new();
        let keys = [1.0f64, 1.5, 1.25, 1.75, 3.0, 5.0];
        for (node, k) in keys.iter().enumerate() {
            heap.push(k.to_bits(), node as u32);
        }
        assert_eq!(heap.pop(), Some(0));
        let mut lowest = Vec::new();
        heap.lowest(2, |node| node != 2, &mut lowest);
        lowest.sort_unstable();
        // The two least keys but the unwanted 1.25: 1.5 and 1.75, whose bucket is below 3's and 5's.
        assert_eq!(lowest, vec![1, 3]);
        lowest.clear();
        heap.lowest(9, |_| true, &mut lowest);
        assert_eq!(lowest.len(), 5, "every entry left");
    }

    #[test]
    fn dijkstra_finds_the_cheaper_detour() {
        let (graph, _) = line_graph();
        let tree = dijkstra(&graph, 0, &[3]);
        assert_eq!(tree.path(3), Some(vec![0, 1, 3]));
        assert_eq!(tree.cost(3), 2.0);
        assert_eq!(tree.edges(3), vec![0, 3]);
        assert_eq!(dijkstra(&graph, 3, &[0]).path(0), None);
    }

    #[test]
    fn astar_agrees_with_dijkstra_on_a_random_graph() {
        let mut rng = karst_scene::rng::Random::stream(1, "test", "astar");
        let n = 400;
        let positions: Vec<[f64; 3]> =
            (0..n).map(|_| [rng.range(0.0, 100.0), rng.range(0.0, 100.0), rng.range(0.0, 20.0)]).collect();
        let lists = (0..n)
            .map(|u| {
                (0..8)
                    .map(|_| {
                        let v = rng.index(n);
                        let d = DVec3::from_array(positions[u]).distance(DVec3::from_array(positions[v]));
                        (v as u32, (d * rng.range(1.0, 3.0)) as f32)
                    })
                    .collect()
            })
            .collect();
        let graph = CostGraph::from_lists(lists);
        let m = min_cost_per_metre(&graph, &positions);
        assert!(m >= 0.99, "{m}");
        for (s, t) in [(0, 1), (5, 300), (17, 42), (399, 2)] {
            let exact = dijkstra(&graph, s, &[t]);
            let guided = astar(&graph, &positions, m, s, t);
            assert!((exact.cost(t) - guided.cost(t)).abs() < 1e-9, "{s}→{t}");
        }
    }

    #[test]
    fn a_search_on_kept_arrays_is_a_search_on_fresh_ones() {
        let mut rng = karst_scene::rng::Random::stream(3, "test", "spare");
        let n = 300;
        let lists = (0..n)
            .map(|_| (0..6).map(|_| (rng.index(n) as u32, rng.range(0.5, 2.0) as f32)).collect())
            .collect();
        let graph = CostGraph::from_lists(lists);
        let trees = |sources: &[usize]| -> Vec<Vec<(f64, Option<Vec<usize>>)>> {
            sources
                .iter()
                .map(|&s| {
                    let tree = dijkstra(&graph, s, &[n - 1 - s]);
                    (0..n).map(|v| (tree.cost(v), tree.path(v))).collect()
                })
                .collect()
        };
        // On this thread the later searches reuse the arrays of the earlier ones; each search of
        // its own thread starts from new arrays.
        let sources = [0, 7, 150, 299, 7];
        let kept = trees(&sources);
        for (i, &s) in sources.iter().enumerate() {
            let fresh = std::thread::scope(|scope| scope.spawn(|| trees(&[s])).join().unwrap());
            assert_eq!(kept[i], fresh[0], "source {s}");
        }
    }

    #[test]
    fn cohesion_makes_used_edges_attractive() {
        let (graph, _) = line_graph();
        let mut used = EdgeSet::new(graph.edge_count());
        used.insert(2); // 0 → 3 direct, 5 × 0.1 = 0.5
        let cohesive = Cohesive { base: &graph, used: &used, factor: 0.1 };
        let tree = dijkstra(&cohesive, 0, &[3]);
        assert_eq!(tree.path(3), Some(vec![0, 3]));
        assert!((tree.cost(3) - 0.5).abs() < 1e-12);
    }

    #[test]
    fn set_search_stops_at_the_cheapest_member() {
        let (graph, _) = line_graph();
        let (tree, reached) = dijkstra_to_set(&graph, 0, |v| v == 2 || v == 3);
        assert_eq!(reached, Some(2));
        assert_eq!(tree.path(2), Some(vec![0, 2]));
    }
}
