//! The cost graph artifact: directed edges in compressed sparse rows.

use serde::{Deserialize, Serialize};

use karst_artifact::{Kind, Payload};

/// Directed graph over the samples: the out-edges of sample `i` are
/// `targets[offsets[i]..offsets[i + 1]]` with costs `costs[..]` at the same indices.
/// 8 bytes per edge plus 4 per sample.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct CostGraph {
    pub offsets: Vec<u32>,
    pub targets: Vec<u32>,
    pub costs: Vec<f32>,
}

impl Payload for CostGraph {
    const KIND: Kind = Kind::Costgraph;
    const SCHEMA: u32 = 1;
}

impl CostGraph {
    /// Number of nodes (samples).
    pub fn node_count(&self) -> usize {
        self.offsets.len().saturating_sub(1)
    }

    /// Number of directed edges.
    pub fn edge_count(&self) -> usize {
        self.targets.len()
    }

    /// Out-edges of `node` as (target, cost).
    pub fn out_edges(&self, node: usize) -> impl Iterator<Item = (usize, f32)> + '_ {
        let range = self.offsets[node] as usize..self.offsets[node + 1] as usize;
        self.targets[range.clone()].iter().map(|&t| t as usize).zip(self.costs[range].iter().copied())
    }

    /// Builds the CSR arrays from per-node out-edge lists, in node order.
    pub fn from_lists(lists: Vec<Vec<(u32, f32)>>) -> Self {
        let mut offsets = Vec::with_capacity(lists.len() + 1);
        let total: usize = lists.iter().map(Vec::len).sum();
        let mut targets = Vec::with_capacity(total);
        let mut costs = Vec::with_capacity(total);
        offsets.push(0);
        for list in lists {
            for (t, c) in list {
                targets.push(t);
                costs.push(c);
            }
            offsets.push(targets.len() as u32);
        }
        CostGraph { offsets, targets, costs }
    }
}
