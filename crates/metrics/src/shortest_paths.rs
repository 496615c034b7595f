//! All-sources traversals of the reduced graph: hop distances and Brandes' betweenness from one
//! BFS per source, conduit-length distances from the fastest method that gives Dijkstra's bits
//! (spec §3 "aspl", "cpd" and `average_SPL(dist_weight=True)`): the hop sums times the quantum
//! or a bit-parallel BFS of unit steps when the lengths are whole multiples of one quantum
//! (`quantum`, `bitbfs`), else Dial's buckets or Dijkstra with a binary heap, one per source.
//!
//! Nodes of hanging trees are not run as sources. Peeling leaves repeatedly (keeping one node
//! of a component that is a tree) leaves the 2-core plus one root per tree component; every
//! peeled node v hangs from a parent p through edge w_v, with size(v) nodes in its subtree
//! (itself included). In its component of n_c nodes, the targets outside v's subtree are reached
//! through p and those inside it one edge closer than from p, so
//! `Σ_t d(v, t) = Σ_t d(p, t) + (n_c − 2 size(v)) w_v` (w_v = 1 in hops). v's Brandes dependency
//! vector equals p's, except that p gains n_c − size(v) − 1 (every path leaving the subtree
//! crosses p) and v loses size(v) − 1 (it is the source, not an intermediate): over the size(v)
//! sources of v's subtree, which all share this difference, p gains size(v)(n_c − size(v) − 1)
//! and v loses size(v)(size(v) − 1), and each kept node's BFS counts for the nodes hanging from
//! it.
//!
//! The traversals themselves stay on the kept nodes: a kept node c stands for the size(c) targets
//! of c and its trees, `Σ_t d(s, t) = Σ_c size(c) d(s, c) + tail(c)` (tail(c): the distances
//! from c to its tree nodes), Brandes' recursion weighs target c by size(c), and c is an
//! intermediate of the size(c) − 1 paths into its trees. Each tree node x lies on the paths from
//! every source of its component into its subtree: n_c (size(x) − 1) dependencies. Real caves
//! have ~30 % leaves in the reduced graph and more in their dead-end trees, which this skips.
//!
//! Brandes' sources are split into [`CHUNKS`] fixed ranges that depend only on the graph; rayon
//! runs the ranges in parallel and their betweenness is summed in range order, so every value is
//! bit-identical whatever the number of threads. Each length sum comes from one source alone, or
//! is an exact integer, so neither the ranges nor the batches change it.

use std::cmp::Reverse;
use std::collections::BinaryHeap;

use rayon::prelude::*;

use crate::bitbfs::{StepGraph, distance_sums};
use crate::graph::Csr;
use crate::quantum::quantize;

/// Number of source ranges (fixed, so results do not depend on the thread count).
const CHUNKS: usize = 64;

/// Per-source distance sums and betweenness over all ordered pairs of the reduced graph.
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct AllPairs {
    /// `Σ_t d(s, t)` in hops, for each source `s` (reachable `t` only).
    pub(crate) hop_sums: Vec<u64>,
    /// `Σ_t d(s, t)` along edge lengths, for each source `s` (reachable `t` only).
    pub(crate) length_sums: Vec<f64>,
    /// Unnormalised betweenness `Σ_{s≠v≠t} σ_st(v) / σ_st` over ordered pairs.
    pub(crate) betweenness: Vec<f64>,
}

/// The graph with its hanging trees peeled off.
struct Trees<'a> {
    adj: &'a Csr,
    lengths: &'a [f64],
    /// For a peeled node: `(parent, edge)`.
    anchor: Vec<Option<(usize, usize)>>,
    /// Peeled nodes, children before their parents.
    peeled: Vec<usize>,
    /// Nodes in the subtree of a peeled node; 1 + the nodes hanging from a kept node.
    size: Vec<usize>,
    /// For a kept node: the hop distances to the nodes hanging from it, summed.
    hop_tail: Vec<u64>,
    /// For a kept node: the conduit-length distances to the nodes hanging from it, summed.
    length_tail: Vec<f64>,
}

impl<'a> Trees<'a> {
    fn new(adj: &'a Csr, lengths: &'a [f64]) -> Self {
        let n = adj.n_nodes();
        let mut degree: Vec<usize> = (0..n).map(|v| adj.degree(v)).collect();
        let mut anchor = vec![None; n];
        let mut size = vec![1; n];
        let mut peeled = Vec::new();
        let mut queue: std::collections::VecDeque<usize> = (0..n).filter(|&v| degree[v] == 1).collect();
        while let Some(v) = queue.pop_front() {
            // Degree 0: the last node of a tree component, kept as its root.
            if degree[v] != 1 {
                continue;
            }
            let Some((p, e)) = adj.incident(v).find(|&(p, _)| anchor[p].is_none() && degree[p] > 0) else {
                continue;
            };
            anchor[v] = Some((p, e));
            peeled.push(v);
            degree[v] = 0;
            degree[p] -= 1;
            size[p] += size[v];
            if degree[p] == 1 {
                queue.push_back(p);
            }
        }
        let (mut hop_tail, mut length_tail) = (vec![0; n], vec![0.0; n]);
        let (mut root, mut hops, mut length) = ((0..n).collect::<Vec<_>>(), vec![0u64; n], vec![0.0; n]);
        for &v in peeled.iter().rev() {
            let Some((p, e)) = anchor[v] else { continue };
            (root[v], hops[v], length[v]) = (root[p], hops[p] + 1, length[p] + lengths[e]);
            hop_tail[root[v]] += hops[v];
            length_tail[root[v]] += length[v];
        }
        Self { adj, lengths, anchor, peeled, size, hop_tail, length_tail }
    }

    fn is_peeled(&self, v: usize) -> bool {
        self.anchor[v].is_some()
    }

    /// Kept neighbours and edges of a kept node.
    fn kept(&self, v: usize) -> impl Iterator<Item = (usize, usize)> + '_ {
        self.adj.incident(v).filter(|&(w, _)| !self.is_peeled(w))
    }
}

/// The kept nodes as a compact graph: ids `0..k` in the original order (so that ties between
/// equal distances break as before), each adjacency list in the original order restricted to
/// kept neighbours, 32-bit ids and the length of every arc beside it: the traversals' inner
/// loops read contiguous memory and test no peeled flag.
struct Kept {
    /// Original id of each kept node.
    nodes: Vec<usize>,
    offsets: Vec<u32>,
    targets: Vec<u32>,
    lengths: Vec<f64>,
    size: Vec<u32>,
    hop_tail: Vec<u64>,
    length_tail: Vec<f64>,
}

impl Kept {
    fn new(trees: &Trees) -> Self {
        let n = trees.adj.n_nodes();
        let nodes: Vec<usize> = (0..n).filter(|&v| !trees.is_peeled(v)).collect();
        let mut index = vec![u32::MAX; n];
        for (k, &v) in nodes.iter().enumerate() {
            index[v] = k as u32;
        }
        let (mut offsets, mut targets, mut lengths) = (vec![0u32], Vec::new(), Vec::new());
        for &v in &nodes {
            for (w, e) in trees.kept(v) {
                targets.push(index[w]);
                lengths.push(trees.lengths[e]);
            }
            offsets.push(targets.len() as u32);
        }
        Self {
            size: nodes.iter().map(|&v| trees.size[v] as u32).collect(),
            hop_tail: nodes.iter().map(|&v| trees.hop_tail[v]).collect(),
            length_tail: nodes.iter().map(|&v| trees.length_tail[v]).collect(),
            nodes,
            offsets,
            targets,
            lengths,
        }
    }

    fn len(&self) -> usize {
        self.nodes.len()
    }

    fn arcs(&self, v: u32) -> std::ops::Range<usize> {
        self.offsets[v as usize] as usize..self.offsets[v as usize + 1] as usize
    }

    /// The bucket width of Dial's algorithm when the arc lengths allow it: all positive and
    /// within a factor [`DIAL_RATIO`] of each other (grids, regular mazes); else None.
    fn dial_width(&self) -> Option<f64> {
        let (lo, hi) =
            self.lengths.iter().fold((f64::INFINITY, 0.0f64), |(lo, hi), &l| (lo.min(l), hi.max(l)));
        (lo > 0.0 && hi <= lo * DIAL_RATIO).then_some(lo * (1.0 - 1e-6))
    }
}

/// Largest ratio of the longest to the shortest arc for Dial's buckets: beyond it the empty
/// buckets between far-apart distances cost more than a heap.
const DIAL_RATIO: f64 = 64.0;

/// How the conduit-length distance sums are found (fastest exact method first).
enum LengthMethod {
    /// Every length is one quantum: the sums are the hop sums times the quantum.
    Hops { quantum: f64 },
    /// Lengths of a few quanta each: bit-parallel BFS on the graph of unit steps.
    Steps { quantum: f64, graph: StepGraph },
    /// Lengths within [`DIAL_RATIO`] of each other: Dial's buckets of this width.
    Dial(f64),
    /// Dijkstra's algorithm with a binary heap.
    Heap,
}

/// Largest number of extra nodes of the unit-step graph per kept node: beyond it the steps cost
/// more than Dial's float buckets.
const STEPS_PER_NODE: usize = 4;

impl LengthMethod {
    fn choose(trees: &Trees, kept: &Kept) -> Self {
        match quantize(trees.lengths, trees.adj.n_nodes()) {
            Some(q) if q.max_unit == 1 => Self::Hops { quantum: q.quantum },
            Some(q) => match step_graph(trees, kept, &q.units) {
                Some(graph) => Self::Steps { quantum: q.quantum, graph },
                None => kept.dial_width().map_or(Self::Heap, Self::Dial),
            },
            None => kept.dial_width().map_or(Self::Heap, Self::Dial),
        }
    }
}

/// The kept graph with every edge of u quanta (`units` by edge id) a chain of u unit steps,
/// unless that adds more than [`STEPS_PER_NODE`] nodes per kept node.
fn step_graph(trees: &Trees, kept: &Kept, units: &[u32]) -> Option<StepGraph> {
    let mut index = vec![u32::MAX; trees.adj.n_nodes()];
    for (k, &v) in kept.nodes.iter().enumerate() {
        index[v] = k as u32;
    }
    let extra: usize = kept
        .nodes
        .iter()
        .flat_map(|&v| trees.kept(v).filter(move |&(w, _)| v < w))
        .map(|(_, e)| units[e] as usize - 1)
        .sum();
    if extra > STEPS_PER_NODE * kept.len() {
        return None;
    }
    let mut n_nodes = kept.len() as u32;
    let mut edges = Vec::new();
    for &v in &kept.nodes {
        for (w, e) in trees.kept(v).filter(|&(w, _)| v < w) {
            let mut from = index[v];
            for _ in 1..units[e] {
                edges.push([from, n_nodes]);
                from = n_nodes;
                n_nodes += 1;
            }
            edges.push([from, index[w]]);
        }
    }
    Some(StepGraph::new(n_nodes as usize, kept.len(), &edges))
}

/// The sums of the distances from a kept node to the nodes hanging from the kept nodes of its
/// component, for the exact (quantized) methods whose sums do not depend on the order of the
/// additions.
struct ComponentTails {
    /// Component of each kept node.
    component: Vec<u32>,
    hops: Vec<u64>,
    lengths: Vec<f64>,
}

impl ComponentTails {
    fn new(trees: &Trees, kept: &Kept) -> Self {
        let (of_node, count) = trees.adj.components();
        let component: Vec<u32> = kept.nodes.iter().map(|&v| of_node[v] as u32).collect();
        let (mut hops, mut lengths) = (vec![0; count], vec![0.0; count]);
        for (k, &c) in component.iter().enumerate() {
            hops[c as usize] += kept.hop_tail[k];
            lengths[c as usize] += kept.length_tail[k];
        }
        Self { component, hops, lengths }
    }
}

/// Runs a BFS (with Brandes' accumulation) and a shortest-length traversal from every kept node
/// and derives the peeled nodes' results from their parents'.
pub(crate) fn all_pairs(adj: &Csr, lengths: &[f64]) -> AllPairs {
    let n = adj.n_nodes();
    let trees = Trees::new(adj, lengths);
    let kept = Kept::new(&trees);
    let tails = ComponentTails::new(&trees, &kept);
    let sources: Vec<u32> = (0..kept.len() as u32).collect();
    let chunk = sources.len().div_ceil(CHUNKS).max(1);
    let parts: Vec<(Vec<u64>, Vec<f64>)> =
        sources.par_chunks(chunk).map(|chunk| brandes_chunk(&kept, chunk)).collect();
    let mut total = AllPairs { hop_sums: vec![0; n], length_sums: vec![0.0; n], betweenness: vec![0.0; n] };
    let mut reach = Vec::with_capacity(kept.len());
    for (part_reach, part_betweenness) in parts {
        reach.extend(part_reach);
        for (k, p) in part_betweenness.into_iter().enumerate() {
            total.betweenness[kept.nodes[k]] += p;
        }
    }
    let length_sums = conduit_length_sums(&kept, &LengthMethod::choose(&trees, &kept), &tails, &reach);
    for (k, &v) in kept.nodes.iter().enumerate() {
        total.hop_sums[v] = reach[k] + tails.hops[tails.component[k] as usize];
        total.length_sums[v] = length_sums[k];
    }
    add_tree_sources(&trees, &mut total);
    total
}

/// `Σ_t d(s, t)` along conduit lengths for every kept source, its trees' targets included;
/// `reach`: the sources' hop sums without the trees' tails.
fn conduit_length_sums(
    kept: &Kept,
    method: &LengthMethod,
    tails: &ComponentTails,
    reach: &[u64],
) -> Vec<f64> {
    // Exact sums (module `quantum`): any order of the additions gives the same bits.
    let exact = |k: usize, steps: u64, quantum: f64| {
        steps as f64 * quantum + tails.lengths[tails.component[k] as usize]
    };
    let sources: Vec<u32> = (0..kept.len() as u32).collect();
    let chunk = sources.len().div_ceil(CHUNKS).max(1);
    match method {
        LengthMethod::Hops { quantum } => {
            reach.iter().enumerate().map(|(k, &r)| exact(k, r, *quantum)).collect()
        }
        LengthMethod::Steps { quantum, graph } => distance_sums(graph, &kept.size)
            .into_iter()
            .enumerate()
            .map(|(k, steps)| exact(k, steps, *quantum))
            .collect(),
        LengthMethod::Dial(width) => sources
            .par_chunks(chunk)
            .flat_map_iter(|chunk| {
                let mut dial = Dial::new(kept.len(), kept, *width);
                chunk.iter().map(|&s| dial.run(kept, s)).collect::<Vec<_>>()
            })
            .collect(),
        LengthMethod::Heap => sources
            .par_chunks(chunk)
            .flat_map_iter(|chunk| {
                let mut dijkstra = Dijkstra::new(kept.len());
                chunk.iter().map(|&s| dijkstra.run(kept, s)).collect::<Vec<_>>()
            })
            .collect(),
    }
}

/// Completes `total` with the contributions of the peeled nodes as sources (module docs).
fn add_tree_sources(trees: &Trees, total: &mut AllPairs) {
    let (component, n_components) = trees.adj.components();
    let mut n_c = vec![0i64; n_components];
    for &c in &component {
        n_c[c] += 1;
    }
    for &v in trees.peeled.iter().rev() {
        let Some((p, e)) = trees.anchor[v] else { continue };
        let (n, size) = (n_c[component[v]], trees.size[v] as i64);
        let shift = n - 2 * size;
        total.hop_sums[v] = total.hop_sums[p].saturating_add_signed(shift);
        total.length_sums[v] = total.length_sums[p] + shift as f64 * trees.lengths[e];
        total.betweenness[p] += (size * (n - size - 1)) as f64;
        // n_c (size − 1) as an intermediate from every source, minus size (size − 1) as a source.
        total.betweenness[v] += ((size - 1) * (n - size)) as f64;
    }
}

/// The hop sums without tails (`Σ_c size(c) d(s, c)`) of one range of sources and the
/// betweenness they add (per kept id).
fn brandes_chunk(kept: &Kept, sources: &[u32]) -> (Vec<u64>, Vec<f64>) {
    let mut bfs = Brandes::new(kept.len());
    let mut betweenness = vec![0.0; kept.len()];
    let reach = sources.iter().map(|&s| bfs.run(kept, s, &mut betweenness)).collect();
    (reach, betweenness)
}

/// Reusable buffers of Brandes' algorithm for unweighted graphs.
struct Brandes {
    dist: Vec<u32>,
    /// Shortest-path count σ and dependency δ of each node, side by side: the backward sweep
    /// reads both of a neighbour from one cache line.
    paths: Vec<Paths>,
    order: Vec<u32>,
}

#[derive(Debug, Clone, Copy, Default)]
struct Paths {
    sigma: f64,
    delta: f64,
}

impl Brandes {
    fn new(n: usize) -> Self {
        Self { dist: vec![u32::MAX; n], paths: vec![Paths::default(); n], order: vec![0; n + 1] }
    }

    /// Adds the dependencies of kept source `s` on kept nodes, times the size(s) sources it
    /// stands for, to `betweenness`; returns `Σ_c size(c) d(s, c)` over the kept nodes c it
    /// reaches (the hop sum without the trees' tails, module docs).
    ///
    /// The buffers of a node are reset as soon as its dependency is final: a node nearer the
    /// source then sees it at distance `u32::MAX`, never one hop farther than itself, since only
    /// the source is at distance 0 and the source's own dependency is not needed. Arcs that are
    /// not on a shortest path add 0 to a dependency instead of branching (unpredictable in a
    /// maze): x + 0 is x for the non-negative counts and dependencies.
    fn run(&mut self, kept: &Kept, s: u32, betweenness: &mut [f64]) -> u64 {
        let reached = self.count_shortest_paths(kept, s);
        let weight = f64::from(kept.size[s as usize]);
        let mut reach = 0;
        for &w in self.order[1..reached].iter().rev() {
            let w = w as usize;
            let dist = self.dist[w];
            let size = kept.size[w];
            reach += u64::from(size) * u64::from(dist);
            let Paths { sigma, delta } = self.paths[w];
            let coeff = (f64::from(size) + delta) / sigma;
            for arc in kept.arcs(w as u32) {
                let v = kept.targets[arc] as usize;
                let on_path = self.dist[v].wrapping_add(1) == dist;
                let paths = &mut self.paths[v];
                paths.delta += if on_path { paths.sigma * coeff } else { 0.0 };
            }
            betweenness[w] += weight * (delta + f64::from(size - 1));
            self.dist[w] = u32::MAX;
            self.paths[w] = Paths::default();
        }
        self.dist[s as usize] = u32::MAX;
        self.paths[s as usize] = Paths::default();
        reach
    }

    /// BFS from `s` over the kept nodes: hop distances, shortest-path counts and the visiting
    /// order in `order[..n]`; returns n, the number of nodes reached.
    fn count_shortest_paths(&mut self, kept: &Kept, s: u32) -> usize {
        self.order[0] = s;
        self.dist[s as usize] = 0;
        self.paths[s as usize].sigma = 1.0;
        let (mut head, mut end) = (0, 1);
        while head < end {
            let v = self.order[head] as usize;
            head += 1;
            let (next, sigma_v) = (self.dist[v] + 1, self.paths[v].sigma);
            for arc in kept.arcs(v as u32) {
                let w = kept.targets[arc] as usize;
                let seen = self.dist[w];
                if seen == u32::MAX {
                    self.dist[w] = next;
                    self.order[end] = w as u32;
                    end += 1;
                    self.paths[w].sigma += sigma_v;
                } else if seen == next {
                    self.paths[w].sigma += sigma_v;
                }
            }
        }
        end
    }
}

/// Reusable buffers of Dijkstra's algorithm.
struct Dijkstra {
    dist: Vec<f64>,
    settled: Vec<u32>,
    done: Vec<bool>,
    /// `(distance bits, node)`: non-negative floats order like their bit patterns.
    heap: BinaryHeap<Reverse<(u64, u32)>>,
}

impl Dijkstra {
    fn new(n: usize) -> Self {
        Self {
            dist: vec![f64::INFINITY; n],
            settled: Vec::with_capacity(n),
            done: vec![false; n],
            heap: BinaryHeap::new(),
        }
    }

    /// `Σ_t d(s, t)` along edge lengths, over the kept nodes and the trees hanging from them.
    fn run(&mut self, kept: &Kept, s: u32) -> f64 {
        self.dist[s as usize] = 0.0;
        self.heap.push(Reverse((0f64.to_bits(), s)));
        while let Some(Reverse((_, node))) = self.heap.pop() {
            let v = node as usize;
            if self.done[v] {
                continue;
            }
            self.done[v] = true;
            self.settled.push(node);
            let d = self.dist[v];
            for arc in kept.arcs(node) {
                let w = kept.targets[arc] as usize;
                let through = d + kept.lengths[arc];
                if !self.done[w] && through < self.dist[w] {
                    self.dist[w] = through;
                    self.heap.push(Reverse((through.to_bits(), w as u32)));
                }
            }
        }
        settled_sum(kept, &mut self.settled, &mut self.dist, &mut self.done)
    }
}

/// `Σ size(v) d(v) + tail(v)` over the settled nodes in settling order (the order of the sum
/// fixes its last bits), then the buffers reset.
fn settled_sum(kept: &Kept, settled: &mut Vec<u32>, dist: &mut [f64], done: &mut [bool]) -> f64 {
    let sum = settled
        .iter()
        .map(|&v| kept.size[v as usize] as f64 * dist[v as usize] + kept.length_tail[v as usize])
        .sum::<f64>();
    for &v in settled.iter() {
        dist[v as usize] = f64::INFINITY;
        done[v as usize] = false;
    }
    settled.clear();
    sum
}

/// Dial's algorithm, for arc lengths within [`DIAL_RATIO`] of each other: distances are
/// bucketed by `width`, a little below the shortest arc, so no arc relaxes a node into its own
/// bucket and every node of a bucket is final when the bucket is reached. A bucket's nodes are
/// settled in (distance, node) order, the order in which the binary heap pops them: the
/// distances, the settling order and hence every bit of the sums are those of [`Dijkstra`],
/// without a heap.
struct Dial {
    dist: Vec<f64>,
    settled: Vec<u32>,
    done: Vec<bool>,
    /// A ring of buckets, enough to span the longest arc.
    buckets: Vec<Vec<u32>>,
    width: f64,
}

impl Dial {
    fn new(n: usize, kept: &Kept, width: f64) -> Self {
        let longest = kept.lengths.iter().copied().fold(0.0, f64::max);
        let ring = (longest / width).ceil() as usize + 2;
        Self {
            dist: vec![f64::INFINITY; n],
            settled: Vec::with_capacity(n),
            done: vec![false; n],
            buckets: vec![Vec::new(); ring],
            width,
        }
    }

    fn bucket(&self, d: f64) -> u64 {
        (d / self.width) as u64
    }

    fn run(&mut self, kept: &Kept, s: u32) -> f64 {
        let ring = self.buckets.len() as u64;
        self.dist[s as usize] = 0.0;
        self.buckets[0].push(s);
        let mut pending = 1usize;
        let mut current = 0u64;
        let mut live = Vec::new();
        while pending > 0 {
            let slot = (current % ring) as usize;
            pending -= self.buckets[slot].len();
            live.clear();
            for &v in &self.buckets[slot] {
                if !self.done[v as usize] && self.bucket(self.dist[v as usize]) == current {
                    live.push(v);
                }
            }
            self.buckets[slot].clear();
            live.sort_unstable_by_key(|&v| (self.dist[v as usize].to_bits(), v));
            live.dedup();
            for &v in &live {
                self.done[v as usize] = true;
                self.settled.push(v);
            }
            for &v in &live {
                let d = self.dist[v as usize];
                for arc in kept.arcs(v) {
                    let w = kept.targets[arc] as usize;
                    let through = d + kept.lengths[arc];
                    if !self.done[w] && through < self.dist[w] {
                        self.dist[w] = through;
                        let slot = (self.bucket(through) % ring) as usize;
                        self.buckets[slot].push(w as u32);
                        pending += 1;
                    }
                }
            }
            current += 1;
        }
        settled_sum(kept, &mut self.settled, &mut self.dist, &mut self.done)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn path_of_three_nodes() {
        let adj = Csr::from_edges(3, &[[0, 1], [1, 2]]);
        let r = all_pairs(&adj, &[1.0, 2.5]);
        assert_eq!(r.hop_sums, vec![3, 2, 3]);
        assert_eq!(r.length_sums, vec![4.5, 3.5, 6.0]);
        // Node 1 is on the paths 0→2 and 2→0.
        assert_eq!(r.betweenness, vec![0.0, 2.0, 0.0]);
    }

    #[test]
    fn square_splits_dependencies_between_the_two_paths() {
        let adj = Csr::from_edges(4, &[[0, 1], [1, 2], [2, 3], [3, 0]]);
        let r = all_pairs(&adj, &[1.0; 4]);
        assert_eq!(r.hop_sums, vec![4; 4]);
        assert_eq!(r.betweenness, vec![1.0; 4]);
    }

    #[test]
    fn leaves_match_a_direct_traversal() {
        // Star 0-{1,2,3} with a tail 3-4: only node 0 is run as a source.
        let adj = Csr::from_edges(5, &[[0, 1], [0, 2], [0, 3], [3, 4]]);
        let r = all_pairs(&adj, &[1.0, 2.0, 3.0, 4.0]);
        assert_eq!(r.hop_sums, vec![5, 8, 8, 6, 9]);
        assert_eq!(r.length_sums, vec![13.0, 16.0, 19.0, 16.0, 28.0]);
        // Node 0 is on 1-2, 1-3, 1-4, 2-3, 2-4 (both ways); node 3 on 0-4, 1-4, 2-4.
        assert_eq!(r.betweenness, vec![10.0, 0.0, 0.0, 6.0, 0.0]);
    }

    #[test]
    fn dead_end_trees_match_a_direct_traversal() {
        // A path 0-1-2-3 (only node 2 is run as a source) and a triangle 4-5-6 with a tree
        // 6-7-8, 7-9 hanging from it.
        let edges = [[0, 1], [1, 2], [2, 3], [4, 5], [5, 6], [6, 4], [6, 7], [7, 8], [7, 9]];
        let adj = Csr::from_edges(10, &edges);
        let lengths = [1.0, 2.0, 3.0, 1.0, 1.0, 1.0, 2.0, 0.5, 4.0];
        let r = all_pairs(&adj, &lengths);
        assert_eq!(r.hop_sums, vec![6, 4, 4, 6, 10, 10, 7, 7, 11, 11]);
        assert_eq!(r.length_sums[0], 1.0 + 3.0 + 6.0);
        assert_eq!(r.length_sums[8], 0.5 + 2.5 + 3.5 + 3.5 + 4.5);
        // Path: nodes 1 and 2 each lie inside 2 unordered pairs; the tree: 6 inside (4|5)×(7,8,9)
        // = 6 pairs, 7 inside (4,5,6)×(8,9) + (8,9) = 7 pairs. Ordered: twice as many.
        assert_eq!(r.betweenness, vec![0.0, 4.0, 4.0, 0.0, 0.0, 0.0, 12.0, 14.0, 0.0, 0.0]);
    }

    /// A side × side grid whose edge `i` has length `length(i)`.
    fn grid(side: usize, length: impl Fn(usize) -> f64) -> (Csr, Vec<f64>) {
        let mut edges = Vec::new();
        for y in 0..side {
            for x in 0..side {
                let v = y * side + x;
                if x + 1 < side {
                    edges.push([v, v + 1]);
                }
                if y + 1 < side {
                    edges.push([v, v + side]);
                }
            }
        }
        let lengths = (0..edges.len()).map(length).collect();
        (Csr::from_edges(side * side, &edges), lengths)
    }

    #[test]
    fn dial_and_the_heap_agree_to_the_last_bit() {
        for (adj, lengths) in [grid(12, |i| 1.0 + (i * 7 % 11) as f64 / 5.5), grid(9, |_| 0.1)] {
            let trees = Trees::new(&adj, &lengths);
            let kept = Kept::new(&trees);
            let width = kept.dial_width().expect("lengths within the ratio");
            let (mut dial, mut heap) = (Dial::new(kept.len(), &kept, width), Dijkstra::new(kept.len()));
            for s in 0..kept.len() as u32 {
                assert_eq!(dial.run(&kept, s).to_bits(), heap.run(&kept, s).to_bits(), "source {s}");
            }
        }
    }

    #[test]
    fn components_do_not_reach_each_other() {
        let adj = Csr::from_edges(4, &[[0, 1], [2, 3]]);
        let r = all_pairs(&adj, &[2.0, 3.0]);
        assert_eq!(r.hop_sums, vec![1; 4]);
        assert_eq!(r.length_sums, vec![2.0, 2.0, 3.0, 3.0]);
    }

    /// A pseudo-random stream of integers below `bound`.
    fn stream(seed: u64) -> impl FnMut(u64) -> u64 {
        let mut state = seed;
        move |bound| {
            state = state.wrapping_mul(6_364_136_223_846_793_005).wrapping_add(1_442_695_040_888_963_407);
            (state >> 33) % bound
        }
    }

    /// Random test graphs with lengths that are whole multiples of `quantum` (1 to `max_unit`
    /// of them): trees, grids with missing edges (hanging trees) and diagonals, random meshes.
    fn random_graphs(seed: u64, quantum: f64, max_unit: u64) -> Vec<(Csr, Vec<f64>)> {
        let mut next = stream(seed);
        let mut graphs = Vec::new();
        let tree: Vec<[usize; 2]> = (1..60).map(|v| [next(v as u64) as usize, v]).collect();
        graphs.push((60, tree));
        let side = 9;
        let mut grid = Vec::new();
        for v in 0..side * side {
            let (x, y) = (v % side, v / side);
            for (ok, w) in [
                (x + 1 < side, v + 1),
                (y + 1 < side, v + side),
                (x + 1 < side && y + 1 < side, v + side + 1),
            ] {
                if ok && next(10) < 6 {
                    grid.push([v, w]);
                }
            }
        }
        graphs.push((side * side, grid));
        let mut mesh = Vec::new();
        let mut seen = std::collections::HashSet::new();
        for v in 1..70usize {
            for _ in 0..1 + next(3) {
                let w = next(v as u64) as usize;
                if seen.insert((w, v)) {
                    mesh.push([w, v]);
                }
            }
        }
        graphs.push((70, mesh));
        graphs
            .into_iter()
            .map(|(n, edges)| {
                let lengths = edges.iter().map(|_| quantum * (1 + next(max_unit)) as f64).collect();
                (Csr::from_edges(n, &edges), lengths)
            })
            .collect()
    }

    /// Every pair's hop and length distances, dependencies summed from one plain BFS (Brandes)
    /// and one plain Dijkstra per node: no tree peeling, no shortcut.
    fn straightforward(adj: &Csr, lengths: &[f64]) -> AllPairs {
        let n = adj.n_nodes();
        let mut total =
            AllPairs { hop_sums: vec![0; n], length_sums: vec![0.0; n], betweenness: vec![0.0; n] };
        for s in 0..n {
            let (mut dist, mut sigma, mut delta) = (vec![usize::MAX; n], vec![0.0; n], vec![0.0; n]);
            let (mut order, mut head) = (vec![s], 0);
            (dist[s], sigma[s]) = (0, 1.0);
            while let Some(&v) = order.get(head) {
                head += 1;
                for &w in adj.neighbors(v) {
                    if dist[w] == usize::MAX {
                        dist[w] = dist[v] + 1;
                        order.push(w);
                    }
                    if dist[w] == dist[v] + 1 {
                        sigma[w] += sigma[v];
                    }
                }
            }
            for &w in order.iter().rev() {
                for &v in adj.neighbors(w) {
                    if dist[v] + 1 == dist[w] {
                        delta[v] += sigma[v] / sigma[w] * (1.0 + delta[w]);
                    }
                }
                if w != s {
                    total.betweenness[w] += delta[w];
                }
            }
            total.hop_sums[s] = order.iter().map(|&v| dist[v] as u64).sum();
            let mut length = vec![f64::INFINITY; n];
            let mut heap = BinaryHeap::from([Reverse((0f64.to_bits(), s))]);
            length[s] = 0.0;
            while let Some(Reverse((bits, v))) = heap.pop() {
                if bits != length[v].to_bits() {
                    continue;
                }
                for (w, e) in adj.incident(v) {
                    if length[v] + lengths[e] < length[w] {
                        length[w] = length[v] + lengths[e];
                        heap.push(Reverse((length[w].to_bits(), w)));
                    }
                }
            }
            total.length_sums[s] = length.iter().filter(|l| l.is_finite()).sum();
        }
        total
    }

    #[test]
    fn fast_paths_match_the_straightforward_traversals() {
        for (seed, quantum, max_unit) in [(1, 10.0, 1), (2, 10.0, 2), (3, 0.25, 3), (4, 1.5, 2), (5, 0.1, 1)]
        {
            for (adj, lengths) in random_graphs(seed, quantum, max_unit) {
                let fast = all_pairs(&adj, &lengths);
                let plain = straightforward(&adj, &lengths);
                assert_eq!(fast.hop_sums, plain.hop_sums, "seed {seed}");
                for (a, b) in fast.length_sums.iter().zip(&plain.length_sums) {
                    // Exact (hence equal) sums for the quantized lengths, 0.1 is not one.
                    if quantum == 0.1 {
                        assert!((a - b).abs() <= 1e-12 * b.abs(), "seed {seed}: {a} {b}");
                    } else {
                        assert_eq!(a.to_bits(), b.to_bits(), "seed {seed}: {a} {b}");
                    }
                }
                for (a, b) in fast.betweenness.iter().zip(&plain.betweenness) {
                    assert!((a - b).abs() <= 1e-9 * b.abs().max(1.0), "seed {seed}: {a} {b}");
                }
            }
        }
    }

    #[test]
    fn exact_length_sums_are_those_of_dijkstra_to_the_last_bit() {
        let mut methods = Vec::new();
        for (seed, quantum, max_unit) in [(6, 10.0, 1), (7, 10.0, 2), (8, 0.5, 4), (9, 3.0, 3)] {
            for (adj, lengths) in random_graphs(seed, quantum, max_unit) {
                let trees = Trees::new(&adj, &lengths);
                let kept = Kept::new(&trees);
                let tails = ComponentTails::new(&trees, &kept);
                let (reach, _) = brandes_chunk(&kept, &(0..kept.len() as u32).collect::<Vec<_>>());
                let method = LengthMethod::choose(&trees, &kept);
                methods.push(match method {
                    LengthMethod::Hops { .. } => "hops",
                    LengthMethod::Steps { .. } => "steps",
                    LengthMethod::Dial(_) | LengthMethod::Heap => "float",
                });
                let fast = conduit_length_sums(&kept, &method, &tails, &reach);
                let heap = conduit_length_sums(&kept, &LengthMethod::Heap, &tails, &reach);
                let bits = |v: &[f64]| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
                assert_eq!(bits(&fast), bits(&heap), "seed {seed}");
            }
        }
        // The trees keep one node, the grids and meshes of 1 quantum take the hop sums.
        assert!(methods.iter().filter(|&&m| m == "steps").count() >= 4, "{methods:?}");
        assert!(methods.iter().filter(|&&m| m == "hops").count() >= 3, "{methods:?}");
    }
}
