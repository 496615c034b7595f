//! Orientation of every link downstream, from the sinks to the springs.
//!
//! A priority flood from the springs ranks the nodes. A node's key is (level, distance):
//! in the vadose zone the level is the node's elevation, raised to its neighbour's level when
//! it lies lower (a low point fills up to its spill height and ponds); in the phreatic zone the
//! level is inherited, so flooded conduits are ordered by their distance to the spring along
//! the network, the cost-to-spring that stands for the hydraulic head. Nodes are ranked in the
//! order the flood reaches them, and every link is directed from its higher-ranked end to its
//! lower-ranked end. A strict order admits no cycle, so loops and mazes are oriented
//! consistently, and every reached node that is not a spring has a lower-ranked neighbour
//! (the one the flood came from): an exit, so water always reaches a spring. Nodes the flood
//! never reaches (parts of the network with no spring) carry no water.

use std::cmp::Ordering;
use std::collections::BinaryHeap;

use karst_skeleton::{Skeleton, Zone};

use crate::graph::Graph;

/// Ranks of the nodes.
#[derive(Debug, Clone, PartialEq)]
pub struct Orientation {
    /// Rank of each node (0 = first reached), `None` when no spring can be reached from it.
    pub rank: Vec<Option<u32>>,
    /// Level of each node, metres: the water surface a ponded vadose node fills up to.
    pub level: Vec<f64>,
    /// Nodes by decreasing rank: the dependency order from sources to wells.
    pub upstream_first: Vec<u32>,
}

#[derive(Debug, Clone, Copy, PartialEq)]
struct Key {
    level: f64,
    distance: f64,
    seq: u64,
    node: u32,
}

impl Eq for Key {}

impl Ord for Key {
    /// Reversed so that `BinaryHeap` pops the lowest (level, distance, seq) first.
    fn cmp(&self, other: &Self) -> Ordering {
        (other.level.total_cmp(&self.level))
            .then(other.distance.total_cmp(&self.distance))
            .then(other.seq.cmp(&self.seq))
    }
}

impl PartialOrd for Key {
    fn partial_cmp(&self, other: &Self) -> Option<Ordering> {
        Some(self.cmp(other))
    }
}

/// Floods `graph` from the `springs` nodes.
pub fn orient(skeleton: &Skeleton, graph: &Graph, springs: &[u32]) -> Orientation {
    let n = graph.positions.len();
    let mut rank = vec![None; n];
    let mut level = vec![f64::NAN; n];
    let mut order = Vec::new();
    let mut heap = BinaryHeap::new();
    let mut seq = 0u64;
    for &s in springs {
        heap.push(Key { level: graph.positions[s as usize].z, distance: 0.0, seq, node: s });
        seq += 1;
    }
    while let Some(key) = heap.pop() {
        let node = key.node;
        if rank[node as usize].is_some() {
            continue;
        }
        rank[node as usize] = Some(order.len() as u32);
        level[node as usize] = key.level;
        order.push(node);
        for &l in &graph.at_node[node as usize] {
            let next = graph.across(l, node);
            if rank[next as usize].is_some() {
                continue;
            }
            let own = match skeleton.nodes[next as usize].zone {
                Zone::Vadose => graph.positions[next as usize].z,
                Zone::Phreatic => f64::NEG_INFINITY,
            };
            let distance = key.distance + graph.length(l);
            heap.push(Key { level: key.level.max(own), distance, seq, node: next });
            seq += 1;
        }
    }
    order.reverse();
    Orientation { rank, level, upstream_first: order }
}

impl Orientation {
    /// (upstream, downstream) ends of `link`, or `None` when it carries no water.
    pub fn direction(&self, graph: &Graph, link: usize) -> Option<(u32, u32)> {
        let l = &graph.links[link];
        match (self.rank[l.a as usize], self.rank[l.b as usize]) {
            (Some(ra), Some(rb)) if ra > rb => Some((l.a, l.b)),
            (Some(ra), Some(rb)) if ra < rb => Some((l.b, l.a)),
            _ => None,
        }
    }
}
