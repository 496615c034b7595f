//! All-sources traversals of the reduced graph: hop distances and Brandes' betweenness from one
//! BFS per source, conduit-length distances from one Dijkstra per source (spec §3 "aspl", "cpd"
//! and `average_SPL(dist_weight=True)`).
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
//! Sources are split into [`CHUNKS`] fixed ranges that depend only on the graph; rayon runs the
//! ranges in parallel and their results are combined in range order, so every value is
//! bit-identical whatever the number of threads.

use std::cmp::Reverse;
use std::collections::BinaryHeap;

use rayon::prelude::*;

use crate::graph::Csr;

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

/// Runs a BFS (with Brandes' accumulation) and a Dijkstra from every kept node and derives the
/// peeled nodes' results from their parents'.
pub(crate) fn all_pairs(adj: &Csr, lengths: &[f64]) -> AllPairs {
    let n = adj.n_nodes();
    let trees = Trees::new(adj, lengths);
    let sources: Vec<usize> = (0..n).filter(|&v| !trees.is_peeled(v)).collect();
    let chunk = sources.len().div_ceil(CHUNKS).max(1);
    let parts: Vec<AllPairs> = sources.par_chunks(chunk).map(|chunk| from_sources(&trees, chunk)).collect();
    let mut total = AllPairs { hop_sums: vec![0; n], length_sums: vec![0.0; n], betweenness: vec![0.0; n] };
    for (part, chunk) in parts.into_iter().zip(sources.chunks(chunk)) {
        for (i, &s) in chunk.iter().enumerate() {
            total.hop_sums[s] = part.hop_sums[i];
            total.length_sums[s] = part.length_sums[i];
        }
        for (b, p) in total.betweenness.iter_mut().zip(part.betweenness) {
            *b += p;
        }
    }
    add_tree_sources(&trees, &mut total);
    total
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

fn from_sources(trees: &Trees, sources: &[usize]) -> AllPairs {
    let n = trees.adj.n_nodes();
    let mut bfs = Brandes::new(n);
    let mut dijkstra = Dijkstra::new(n);
    let mut betweenness = vec![0.0; n];
    let hop_sums = sources.iter().map(|&s| bfs.run(trees, s, &mut betweenness)).collect();
    let length_sums = sources.iter().map(|&s| dijkstra.run(trees, s)).collect();
    AllPairs { hop_sums, length_sums, betweenness }
}

/// Reusable buffers of Brandes' algorithm for unweighted graphs.
struct Brandes {
    dist: Vec<usize>,
    sigma: Vec<f64>,
    delta: Vec<f64>,
    order: Vec<usize>,
}

impl Brandes {
    fn new(n: usize) -> Self {
        Self {
            dist: vec![usize::MAX; n],
            sigma: vec![0.0; n],
            delta: vec![0.0; n],
            order: Vec::with_capacity(n),
        }
    }

    /// Adds the dependencies of kept source `s` on kept nodes, times the size(s) sources it
    /// stands for, to `betweenness`; returns `Σ_t d(s, t)` over all targets (module docs).
    fn run(&mut self, trees: &Trees, s: usize, betweenness: &mut [f64]) -> u64 {
        self.count_shortest_paths(trees, s);
        let weight = trees.size[s] as f64;
        for &w in self.order.iter().rev() {
            let coeff = (trees.size[w] as f64 + self.delta[w]) / self.sigma[w];
            for (v, _) in trees.kept(w) {
                if self.dist[v] + 1 == self.dist[w] {
                    self.delta[v] += self.sigma[v] * coeff;
                }
            }
            if w != s {
                betweenness[w] += weight * (self.delta[w] + (trees.size[w] - 1) as f64);
            }
        }
        let hop_sum =
            self.order.iter().map(|&v| trees.size[v] as u64 * self.dist[v] as u64 + trees.hop_tail[v]).sum();
        for &v in &self.order {
            self.dist[v] = usize::MAX;
            self.sigma[v] = 0.0;
            self.delta[v] = 0.0;
        }
        hop_sum
    }

    /// BFS from `s` over the kept nodes: hop distances, shortest-path counts, visiting order.
    fn count_shortest_paths(&mut self, trees: &Trees, s: usize) {
        self.order.clear();
        self.order.push(s);
        self.dist[s] = 0;
        self.sigma[s] = 1.0;
        let mut head = 0;
        while let Some(&v) = self.order.get(head) {
            head += 1;
            for (w, _) in trees.kept(v) {
                if self.dist[w] == usize::MAX {
                    self.dist[w] = self.dist[v] + 1;
                    self.order.push(w);
                }
                if self.dist[w] == self.dist[v] + 1 {
                    self.sigma[w] += self.sigma[v];
                }
            }
        }
    }
}

/// Reusable buffers of Dijkstra's algorithm.
struct Dijkstra {
    dist: Vec<f64>,
    settled: Vec<usize>,
    done: Vec<bool>,
    /// `(distance bits, node)`: non-negative floats order like their bit patterns.
    heap: BinaryHeap<Reverse<(u64, usize)>>,
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
    fn run(&mut self, trees: &Trees, s: usize) -> f64 {
        self.dist[s] = 0.0;
        self.heap.push(Reverse((0f64.to_bits(), s)));
        while let Some(Reverse((_, node))) = self.heap.pop() {
            if self.done[node] {
                continue;
            }
            self.done[node] = true;
            self.settled.push(node);
            let d = self.dist[node];
            for (w, e) in trees.kept(node) {
                let through = d + trees.lengths[e];
                if !self.done[w] && through < self.dist[w] {
                    self.dist[w] = through;
                    self.heap.push(Reverse((through.to_bits(), w)));
                }
            }
        }
        let sum = self
            .settled
            .iter()
            .map(|&v| trees.size[v] as f64 * self.dist[v] + trees.length_tail[v])
            .sum::<f64>();
        for &v in &self.settled {
            self.dist[v] = f64::INFINITY;
            self.done[v] = false;
        }
        self.settled.clear();
        sum
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

    #[test]
    fn components_do_not_reach_each_other() {
        let adj = Csr::from_edges(4, &[[0, 1], [2, 3]]);
        let r = all_pairs(&adj, &[2.0, 3.0]);
        assert_eq!(r.hop_sums, vec![1; 4]);
        assert_eq!(r.length_sums, vec![2.0, 2.0, 3.0, 3.0]);
    }
}
