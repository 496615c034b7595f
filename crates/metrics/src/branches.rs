//! Branch extraction on the full graph (spec §1).
//!
//! Seeds are the nodes of degree ≠ 2, plus one node per component made only of degree-2 nodes
//! (an isolated cycle). From every seed, every incident edge not yet used starts a walk that goes
//! straight through degree-2 nodes and stops at the first node of degree ≠ 2 or back at its start.
//! karstnet discards a walk that is the reverse of a known branch; skipping walks whose first edge
//! is already used is the same rule, since each edge belongs to exactly one branch.
//!
//! Seeds are visited in karstnet's node order, so each branch starts at the same end as in
//! karstnet. For an isolated cycle karstnet takes the last node of its component: we take the
//! last in node order, which is karstnet's choice whenever the cycle holds more than half of the
//! graph's nodes (otherwise karstnet iterates a Python set; only piece lengths differ, see
//! `reduced`).

use crate::graph::FullGraph;

/// A branch as its node path; a looping branch starts and ends at the same node.
pub(crate) type Branch = Vec<usize>;

/// All branches of the full graph, in karstnet's discovery order.
pub(crate) fn extract(g: &FullGraph) -> Vec<Branch> {
    let mut used = vec![false; g.edges.len()];
    let mut branches = Vec::new();
    for seed in seeds(g) {
        for (next, edge) in g.adj.incident(seed) {
            if !used[edge] {
                branches.push(walk(g, seed, next, edge, &mut used));
            }
        }
    }
    branches
}

/// Whether a branch is a closed conduit (first node = last node).
pub(crate) fn is_loop(branch: &[usize]) -> bool {
    branch.first() == branch.last()
}

/// Nodes of degree ≠ 2 in node order, then the last node of every all-degree-2 component.
fn seeds(g: &FullGraph) -> Vec<usize> {
    let n = g.n_nodes();
    let (component, n_components) = g.adj.components();
    let mut has_seed = vec![false; n_components];
    let mut last_node = vec![0; n_components];
    let mut seeds = Vec::new();
    for v in 0..n {
        last_node[component[v]] = v;
        if g.adj.degree(v) != 2 {
            has_seed[component[v]] = true;
            seeds.push(v);
        }
    }
    seeds.extend((0..n_components).filter(|&c| !has_seed[c]).map(|c| last_node[c]));
    seeds
}

/// Follows `start → next → …` through degree-2 nodes, marking the edges it uses.
fn walk(g: &FullGraph, start: usize, next: usize, edge: usize, used: &mut [bool]) -> Branch {
    let mut path = vec![start, next];
    used[edge] = true;
    let (mut current, mut arrived_by) = (next, edge);
    while current != start && g.adj.degree(current) == 2 {
        let Some((to, by)) = g.adj.incident(current).find(|&(_, e)| e != arrived_by) else {
            break;
        };
        path.push(to);
        used[by] = true;
        (current, arrived_by) = (to, by);
    }
    path
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::network::Network;

    fn graph(links: &[[usize; 2]]) -> FullGraph {
        let n = links.iter().flatten().max().map_or(0, |m| m + 1);
        FullGraph::build(&Network {
            nodes: (0..n).map(|i| [i as f64, (i * i) as f64, 0.0]).collect(),
            links: links.to_vec(),
        })
    }

    #[test]
    fn chain_is_one_branch() {
        assert_eq!(extract(&graph(&[[0, 1], [1, 2], [2, 3]])), vec![vec![0, 1, 2, 3]]);
    }

    #[test]
    fn isolated_cycle_is_one_loop_from_its_last_node() {
        let branches = extract(&graph(&[[0, 1], [1, 2], [2, 3], [3, 0]]));
        assert_eq!(branches, vec![vec![3, 2, 1, 0, 3]]);
        assert!(is_loop(&branches[0]));
    }

    #[test]
    fn loop_on_a_junction_and_parallel_conduits() {
        // 0-1 stem, loop 1-2-3-1, two conduits 1-4-5 and 1-5 plus a tail 5-6.
        let links = [[0, 1], [1, 2], [2, 3], [3, 1], [1, 4], [4, 5], [1, 5], [5, 6]];
        let branches = extract(&graph(&links));
        assert_eq!(branches, vec![vec![0, 1], vec![1, 2, 3, 1], vec![1, 4, 5], vec![1, 5], vec![5, 6]]);
    }
}
