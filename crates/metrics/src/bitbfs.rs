//! Bit-parallel breadth-first search: the distance sums of 64 sources at once.
//!
//! Each node holds a 64-bit word per state (seen, frontier, next): bit j says whether source j
//! has reached the node, reached it at the current level, or reaches it at the next one. One
//! level advances every source with one OR of words per arc instead of 64 separate queue
//! operations, and the work of a batch of nearby sources is shared, since their frontiers sweep
//! over the same nodes at nearly the same levels: sources are batched by growing a ball of
//! ungrouped nodes from each ungrouped node in turn. The sums are integers, so neither the
//! batching nor the order of the batches changes a bit of the result.
//!
//! Used on the unit-step graph of quantized lengths (`quantum`): every arc of u quanta is a chain
//! of u unit steps through u − 1 extra nodes, which count as neither sources nor targets.

use rayon::prelude::*;

/// An undirected graph whose first `real` nodes are the sources and targets.
pub(crate) struct StepGraph {
    offsets: Vec<u32>,
    targets: Vec<u32>,
    real: usize,
}

impl StepGraph {
    /// The graph of `n_nodes` nodes and the unit steps `edges`; nodes `0..real` count.
    pub(crate) fn new(n_nodes: usize, real: usize, edges: &[[u32; 2]]) -> Self {
        let mut offsets = vec![0u32; n_nodes + 1];
        for &[a, b] in edges {
            offsets[a as usize + 1] += 1;
            offsets[b as usize + 1] += 1;
        }
        for v in 0..n_nodes {
            offsets[v + 1] += offsets[v];
        }
        let mut fill = offsets.clone();
        let mut targets = vec![0u32; 2 * edges.len()];
        for &[a, b] in edges {
            for (from, to) in [(a, b), (b, a)] {
                targets[fill[from as usize] as usize] = to;
                fill[from as usize] += 1;
            }
        }
        Self { offsets, targets, real }
    }

    fn n_nodes(&self) -> usize {
        self.offsets.len() - 1
    }

    fn neighbors(&self, v: u32) -> &[u32] {
        &self.targets[self.offsets[v as usize] as usize..self.offsets[v as usize + 1] as usize]
    }
}

/// `Σ_t weight(t) d(s, t)` over the real nodes t reached from each real source s (in steps).
pub(crate) fn distance_sums(graph: &StepGraph, weight: &[u32]) -> Vec<u64> {
    let batches = batches(graph);
    let sums: Vec<Vec<u64>> = batches
        .par_iter()
        .map_init(|| Levels::new(graph.n_nodes()), |levels, batch| levels.run(graph, weight, batch))
        .collect();
    let mut total = vec![0; graph.real];
    for (batch, sums) in batches.iter().zip(sums) {
        for (&s, sum) in batch.iter().zip(sums) {
            total[s as usize] = sum;
        }
    }
    total
}

/// Groups of at most 64 nearby real nodes covering every real node: from each ungrouped node in
/// node order, a breadth-first search through ungrouped real nodes takes the nearest ones.
fn batches(graph: &StepGraph) -> Vec<Vec<u32>> {
    let mut grouped = vec![false; graph.real];
    let mut batches = Vec::new();
    let mut queue = Vec::new();
    for start in 0..graph.real as u32 {
        if grouped[start as usize] {
            continue;
        }
        grouped[start as usize] = true;
        queue.clear();
        queue.push(start);
        let mut head = 0;
        while head < queue.len() && queue.len() < 64 {
            let v = queue[head];
            head += 1;
            for &w in graph.neighbors(v) {
                if (w as usize) < graph.real && !grouped[w as usize] && queue.len() < 64 {
                    grouped[w as usize] = true;
                    queue.push(w);
                }
            }
        }
        batches.push(queue.clone());
    }
    batches
}

/// Reusable per-node words of one batch.
struct Levels {
    seen: Vec<u64>,
    frontier: Vec<u64>,
    next: Vec<u64>,
    active: Vec<u32>,
    reached: Vec<u32>,
}

impl Levels {
    fn new(n: usize) -> Self {
        Self {
            seen: vec![0; n],
            frontier: vec![0; n],
            next: vec![0; n],
            active: Vec::new(),
            reached: Vec::new(),
        }
    }

    /// The distance sums of the sources of `batch` (bit j: `batch[j]`).
    fn run(&mut self, graph: &StepGraph, weight: &[u32], batch: &[u32]) -> Vec<u64> {
        let mut sums = vec![0u64; batch.len()];
        self.active.clear();
        for (j, &s) in batch.iter().enumerate() {
            self.seen[s as usize] |= 1 << j;
            self.frontier[s as usize] |= 1 << j;
            self.active.push(s);
        }
        let mut level = 0u64;
        while !self.active.is_empty() {
            level += 1;
            for &v in &self.active {
                let bits = self.frontier[v as usize];
                for &w in graph.neighbors(v) {
                    let w = w as usize;
                    let new = bits & !self.seen[w];
                    if new != 0 {
                        if self.next[w] == 0 {
                            self.reached.push(w as u32);
                        }
                        self.next[w] |= new;
                    }
                }
            }
            for &v in &self.active {
                self.frontier[v as usize] = 0;
            }
            self.active.clear();
            for &w in &self.reached {
                let w = w as usize;
                let mut new = self.next[w];
                self.next[w] = 0;
                self.seen[w] |= new;
                self.frontier[w] = new;
                if w < graph.real {
                    let add = u64::from(weight[w]) * level;
                    while new != 0 {
                        sums[new.trailing_zeros() as usize] += add;
                        new &= new - 1;
                    }
                }
            }
            std::mem::swap(&mut self.active, &mut self.reached);
        }
        self.seen.iter_mut().for_each(|word| *word = 0);
        sums
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn path_with_a_two_step_arc_and_two_components() {
        // Real 0-1-2 with 1-2 two steps through extra node 5; real 3-4 apart.
        let graph = StepGraph::new(6, 5, &[[0, 1], [1, 5], [5, 2], [3, 4]]);
        assert_eq!(distance_sums(&graph, &[1; 5]), vec![1 + 3, 1 + 2, 3 + 2, 1, 1]);
        assert_eq!(distance_sums(&graph, &[1, 2, 3, 1, 1]), vec![2 + 9, 1 + 6, 3 + 4, 1, 1]);
    }
}
