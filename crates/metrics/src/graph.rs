//! Simple undirected graphs in compressed (CSR) form, built the way networkx builds karstnet's
//! `kg.graph` (spec §0).
//!
//! Node order and neighbour order replicate `nx.Graph().add_edges_from(links)`: nodes are numbered
//! by first appearance in the link list and each adjacency list keeps edge insertion order. No
//! metric of `characterize_graph()` depends on these orders, but karstnet's choice of branch
//! direction — and hence where the reduced graph cuts loops and parallel conduits, which moves
//! the piece lengths used by the length-weighted aspl — does (see `reduced`).

use std::collections::HashSet;

use crate::network::Network;

/// Adjacency lists in one array; `edge_ids` gives the edge behind each adjacency entry.
#[derive(Debug, Clone)]
pub(crate) struct Csr {
    offsets: Vec<usize>,
    targets: Vec<usize>,
    edge_ids: Vec<usize>,
}

impl Csr {
    /// Builds the adjacency of `n_nodes` nodes; each list follows the order of `edges`.
    pub(crate) fn from_edges(n_nodes: usize, edges: &[[usize; 2]]) -> Self {
        let mut offsets = vec![0; n_nodes + 1];
        for &[a, b] in edges {
            offsets[a + 1] += 1;
            offsets[b + 1] += 1;
        }
        for v in 0..n_nodes {
            offsets[v + 1] += offsets[v];
        }
        let mut fill = offsets.clone();
        let mut targets = vec![0; 2 * edges.len()];
        let mut edge_ids = vec![0; 2 * edges.len()];
        for (e, &[a, b]) in edges.iter().enumerate() {
            for (from, to) in [(a, b), (b, a)] {
                targets[fill[from]] = to;
                edge_ids[fill[from]] = e;
                fill[from] += 1;
            }
        }
        Self { offsets, targets, edge_ids }
    }

    pub(crate) fn n_nodes(&self) -> usize {
        self.offsets.len() - 1
    }

    pub(crate) fn n_edges(&self) -> usize {
        self.targets.len() / 2
    }

    pub(crate) fn degree(&self, v: usize) -> usize {
        self.offsets[v + 1] - self.offsets[v]
    }

    /// Neighbours of `v`, in edge insertion order.
    pub(crate) fn neighbors(&self, v: usize) -> &[usize] {
        &self.targets[self.offsets[v]..self.offsets[v + 1]]
    }

    /// `(neighbour, edge id)` pairs of `v`, in edge insertion order.
    pub(crate) fn incident(&self, v: usize) -> impl Iterator<Item = (usize, usize)> + '_ {
        let range = self.offsets[v]..self.offsets[v + 1];
        self.targets[range.clone()].iter().copied().zip(self.edge_ids[range].iter().copied())
    }

    /// Connected components: a component id per node, ids numbered by smallest node (the order
    /// of `nx.connected_components`), and the number of components.
    pub(crate) fn components(&self) -> (Vec<usize>, usize) {
        let mut id = vec![usize::MAX; self.n_nodes()];
        let mut count = 0;
        let mut stack = Vec::new();
        for root in 0..self.n_nodes() {
            if id[root] != usize::MAX {
                continue;
            }
            id[root] = count;
            stack.push(root);
            while let Some(v) = stack.pop() {
                for &w in self.neighbors(v) {
                    if id[w] == usize::MAX {
                        id[w] = count;
                        stack.push(w);
                    }
                }
            }
            count += 1;
        }
        (id, count)
    }
}

/// karstnet's full graph: the nodes that appear in a link, and each undirected link once.
#[derive(Debug, Clone)]
pub(crate) struct FullGraph {
    /// Coordinates, indexed by graph node.
    pub(crate) pos: Vec<[f64; 3]>,
    /// Unique edges in first-appearance order.
    pub(crate) edges: Vec<[usize; 2]>,
    pub(crate) adj: Csr,
}

impl FullGraph {
    /// Builds the graph of a network that passed [`Network::validate`].
    pub(crate) fn build(net: &Network) -> Self {
        let mut local = vec![usize::MAX; net.nodes.len()];
        let mut pos = Vec::new();
        let mut seen = HashSet::with_capacity(net.links.len());
        let mut edges = Vec::with_capacity(net.links.len());
        for link in &net.links {
            let [a, b] = link.map(|node| {
                if local[node] == usize::MAX {
                    local[node] = pos.len();
                    pos.push(net.nodes[node]);
                }
                local[node]
            });
            if seen.insert((a.min(b), a.max(b))) {
                edges.push([a, b]);
            }
        }
        let adj = Csr::from_edges(pos.len(), &edges);
        Self { pos, edges, adj }
    }

    pub(crate) fn n_nodes(&self) -> usize {
        self.pos.len()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn builds_networkx_order_and_collapses_duplicates() {
        let net = Network {
            nodes: (0..5).map(|i| [i as f64, 0.0, 0.0]).collect(),
            links: vec![[3, 1], [1, 3], [1, 4], [4, 1], [0, 2]],
        };
        let g = FullGraph::build(&net);
        assert_eq!(g.pos[0], [3.0, 0.0, 0.0]);
        assert_eq!(g.edges, vec![[0, 1], [1, 2], [3, 4]]);
        assert_eq!(g.adj.neighbors(1), &[0, 2]);
        assert_eq!(g.adj.incident(2).collect::<Vec<_>>(), vec![(1, 1)]);
        assert_eq!(g.adj.components(), (vec![0, 0, 0, 1, 1], 2));
        assert_eq!(g.adj.n_edges(), 3);
    }
}
