//! All-sources traversals of the reduced graph: hop distances and Brandes' betweenness from one
//! BFS per source, conduit-length distances from one Dijkstra per source (spec §3 "aspl", "cpd"
//! and `average_SPL(dist_weight=True)`).
//!
//! Leaves are not run as sources. A leaf ℓ hanging from node p (of degree > 1) reaches every other
//! node of its component of n_c nodes through p, so `Σ_t d(ℓ, t) = Σ_t d(p, t) + (n_c − 2) w_ℓ`
//! (w_ℓ: the leaf edge's length, 1 in hops), its Brandes dependencies equal p's on every node but
//! p, and p gains n_c − 2 (all of ℓ's paths cross it). Dijkstra also settles leaves without the
//! heap. Real caves have ~30 % leaves in the reduced graph, which this skips.
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

/// The graph with its leaves singled out.
struct Leaves<'a> {
    adj: &'a Csr,
    lengths: &'a [f64],
    /// For a leaf whose neighbour has degree > 1: `(neighbour, edge)`.
    anchor: Vec<Option<(usize, usize)>>,
    /// Leaves hanging from each node.
    count: Vec<usize>,
}

impl<'a> Leaves<'a> {
    fn new(adj: &'a Csr, lengths: &'a [f64]) -> Self {
        let n = adj.n_nodes();
        let mut anchor = vec![None; n];
        let mut count = vec![0; n];
        for v in (0..n).filter(|&v| adj.degree(v) == 1) {
            if let Some((p, e)) = adj.incident(v).find(|&(p, _)| adj.degree(p) > 1) {
                anchor[v] = Some((p, e));
                count[p] += 1;
            }
        }
        Self { adj, lengths, anchor, count }
    }

    fn is_leaf(&self, v: usize) -> bool {
        self.anchor[v].is_some()
    }
}

/// Runs a BFS (with Brandes' accumulation) and a Dijkstra from every non-leaf node and derives
/// the leaves' results from their neighbours'.
pub(crate) fn all_pairs(adj: &Csr, lengths: &[f64]) -> AllPairs {
    let n = adj.n_nodes();
    let leaves = Leaves::new(adj, lengths);
    let sources: Vec<usize> = (0..n).filter(|&v| !leaves.is_leaf(v)).collect();
    let chunk = sources.len().div_ceil(CHUNKS).max(1);
    let parts: Vec<AllPairs> = sources.par_chunks(chunk).map(|chunk| from_sources(&leaves, chunk)).collect();
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
    add_leaf_sources(&leaves, &mut total);
    total
}

/// Completes `total` with the contributions of the leaves as sources.
fn add_leaf_sources(leaves: &Leaves, total: &mut AllPairs) {
    let (component, n_components) = leaves.adj.components();
    let mut size = vec![0usize; n_components];
    for &c in &component {
        size[c] += 1;
    }
    for (leaf, anchor) in leaves.anchor.iter().enumerate() {
        if let Some((p, e)) = *anchor {
            let others = size[component[leaf]] - 2;
            total.hop_sums[leaf] = total.hop_sums[p] + others as u64;
            total.length_sums[leaf] = total.length_sums[p] + others as f64 * leaves.lengths[e];
            total.betweenness[p] += others as f64;
        }
    }
}

fn from_sources(leaves: &Leaves, sources: &[usize]) -> AllPairs {
    let n = leaves.adj.n_nodes();
    let mut bfs = Brandes::new(n);
    let mut dijkstra = Dijkstra::new(n);
    let mut betweenness = vec![0.0; n];
    let hop_sums = sources
        .iter()
        .map(|&s| {
            let weight = 1.0 + leaves.count[s] as f64;
            bfs.run(leaves.adj, s, weight, &mut betweenness)
        })
        .collect();
    let length_sums = sources.iter().map(|&s| dijkstra.run(leaves, s)).collect();
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

    /// Adds `weight` times the dependencies of source `s` to `betweenness`; returns `Σ_t d(s, t)`.
    fn run(&mut self, adj: &Csr, s: usize, weight: f64, betweenness: &mut [f64]) -> u64 {
        self.count_shortest_paths(adj, s);
        for &w in self.order.iter().rev() {
            let coeff = (1.0 + self.delta[w]) / self.sigma[w];
            for &v in adj.neighbors(w) {
                if self.dist[v] + 1 == self.dist[w] {
                    self.delta[v] += self.sigma[v] * coeff;
                }
            }
            if w != s {
                betweenness[w] += weight * self.delta[w];
            }
        }
        let hop_sum = self.order.iter().map(|&v| self.dist[v] as u64).sum();
        for &v in &self.order {
            self.dist[v] = usize::MAX;
            self.sigma[v] = 0.0;
            self.delta[v] = 0.0;
        }
        hop_sum
    }

    /// BFS from `s`: hop distances, shortest-path counts and the visiting order.
    fn count_shortest_paths(&mut self, adj: &Csr, s: usize) {
        self.order.clear();
        self.order.push(s);
        self.dist[s] = 0;
        self.sigma[s] = 1.0;
        let mut head = 0;
        while let Some(&v) = self.order.get(head) {
            head += 1;
            for &w in adj.neighbors(v) {
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

    /// `Σ_t d(s, t)` along edge lengths; leaves are settled from their neighbour directly.
    fn run(&mut self, leaves: &Leaves, s: usize) -> f64 {
        let mut leaf_sum = 0.0;
        self.dist[s] = 0.0;
        self.heap.push(Reverse((0f64.to_bits(), s)));
        while let Some(Reverse((_, node))) = self.heap.pop() {
            if self.done[node] {
                continue;
            }
            self.done[node] = true;
            self.settled.push(node);
            let d = self.dist[node];
            for (w, e) in leaves.adj.incident(node) {
                let through = d + leaves.lengths[e];
                if leaves.is_leaf(w) {
                    leaf_sum += through;
                } else if !self.done[w] && through < self.dist[w] {
                    self.dist[w] = through;
                    self.heap.push(Reverse((through.to_bits(), w)));
                }
            }
        }
        let sum = self.settled.iter().map(|&v| self.dist[v]).sum::<f64>() + leaf_sum;
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
        // Star 0-{1,2,3} with a tail 3-4: leaves 1, 2 and 4 are not run as sources.
        let adj = Csr::from_edges(5, &[[0, 1], [0, 2], [0, 3], [3, 4]]);
        let r = all_pairs(&adj, &[1.0, 2.0, 3.0, 4.0]);
        assert_eq!(r.hop_sums, vec![5, 8, 8, 6, 9]);
        assert_eq!(r.length_sums, vec![13.0, 16.0, 19.0, 16.0, 28.0]);
        // Node 0 is on 1-2, 1-3, 1-4, 2-3, 2-4 (both ways); node 3 on 0-4, 1-4, 2-4.
        assert_eq!(r.betweenness, vec![10.0, 0.0, 0.0, 6.0, 0.0]);
    }

    #[test]
    fn components_do_not_reach_each_other() {
        let adj = Csr::from_edges(4, &[[0, 1], [2, 3]]);
        let r = all_pairs(&adj, &[2.0, 3.0]);
        assert_eq!(r.hop_sums, vec![1; 4]);
        assert_eq!(r.length_sums, vec![2.0, 2.0, 3.0, 3.0]);
    }
}
