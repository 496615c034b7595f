//! Dijkstra's shortest paths over the cost graph's compressed rows, with predecessors.
//!
//! Costs are f64 sums of the (positive) edge costs; the heap orders by the cost's bits, which
//! keep the order of non-negative floats, then by node index, so results are deterministic.

use std::cmp::Reverse;
use std::collections::BinaryHeap;

use karst_costgraph::CostGraph;

/// No predecessor.
const NONE: u32 = u32::MAX;

/// Shortest-path tree from one source.
pub struct ShortestPaths {
    cost: Vec<f64>,
    predecessor: Vec<u32>,
}

impl ShortestPaths {
    /// Runs Dijkstra from `source` in cost set `set` until every node of `targets` is settled
    /// (or everything reachable is).
    pub fn from(graph: &CostGraph, set: usize, source: usize, targets: &[usize]) -> Self {
        let n = graph.node_count();
        let mut cost = vec![f64::INFINITY; n];
        let mut predecessor = vec![NONE; n];
        let mut settled = vec![false; n];
        let mut remaining = targets.len();
        let mut heap = BinaryHeap::new();
        cost[source] = 0.0;
        heap.push(Reverse((0f64.to_bits(), source as u32)));
        while let Some(Reverse((bits, node))) = heap.pop() {
            let u = node as usize;
            if settled[u] || f64::from_bits(bits) > cost[u] {
                continue;
            }
            settled[u] = true;
            if targets.contains(&u) {
                remaining -= 1;
                if remaining == 0 {
                    break;
                }
            }
            for (v, c) in graph.out_edges_in(set, u) {
                let through = cost[u] + f64::from(c);
                if through < cost[v] {
                    cost[v] = through;
                    predecessor[v] = node;
                    heap.push(Reverse((through.to_bits(), v as u32)));
                }
            }
        }
        ShortestPaths { cost, predecessor }
    }

    /// Cost of the least-cost path to `target`; infinite when unreachable.
    pub fn cost(&self, target: usize) -> f64 {
        self.cost[target]
    }

    /// The path source → target as node indices, or None when unreachable.
    pub fn path(&self, target: usize) -> Option<Vec<usize>> {
        if !self.cost[target].is_finite() {
            return None;
        }
        let mut path = vec![target];
        let mut at = target;
        while self.predecessor[at] != NONE {
            at = self.predecessor[at] as usize;
            path.push(at);
        }
        path.reverse();
        Some(path)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn finds_the_cheaper_detour() {
        // 0 → 1 → 3 costs 2; 0 → 3 direct costs 5; 0 → 2 → 3 costs 3.
        let graph = CostGraph::from_lists(vec![
            vec![(1, 1.0), (2, 1.0), (3, 5.0)],
            vec![(3, 1.0)],
            vec![(3, 2.0)],
            vec![],
        ]);
        let sp = ShortestPaths::from(&graph, 0, 0, &[3]);
        assert_eq!(sp.path(3), Some(vec![0, 1, 3]));
        assert_eq!(sp.cost(3), 2.0);
        let back = ShortestPaths::from(&graph, 0, 3, &[0]);
        assert_eq!(back.path(0), None);
    }
}
