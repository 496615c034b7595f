//! The simplified ("reduced") graph, karstnet's `kg.graph_simpl` (spec §2).
//!
//! Every branch becomes one edge between its end nodes, except where that would lose a cycle:
//! a looping branch of L nodes is cut into three pieces at nodes ⌊L/3⌋ and 2⌊L/3⌋, and branches
//! sharing their (first, last) nodes with another branch are cut in two at node ⌊L/2⌋ (a direct
//! one-edge branch stays whole). Each piece is an edge weighted by its length along the conduit.
//!
//! The topology never depends on where the cuts fall, but the piece lengths do: they follow the
//! direction in which `branches` found each branch (karstnet's order), so only the length-weighted
//! aspl depends on node numbering and link order — exactly as in karstnet.

use std::collections::HashMap;

use crate::branches::{Branch, is_loop};
use crate::geometry::distance;
use crate::graph::{Csr, FullGraph};

/// The reduced graph: unweighted topology plus the conduit length of each edge.
#[derive(Debug, Clone)]
pub(crate) struct Reduced {
    pub(crate) adj: Csr,
    /// Length of each reduced edge (indexed by edge id of `adj`).
    pub(crate) lengths: Vec<f64>,
}

impl Reduced {
    pub(crate) fn build(g: &FullGraph, branches: &[Branch]) -> Self {
        let mut multiplicity: HashMap<(usize, usize), usize> = HashMap::new();
        for b in branches {
            *multiplicity.entry(ends(b)).or_default() += 1;
        }
        let mut index = vec![usize::MAX; g.n_nodes()];
        let mut n_nodes = 0;
        let mut edges = Vec::new();
        let mut lengths = Vec::new();
        for b in branches {
            for piece in pieces(b, multiplicity[&ends(b)] > 1) {
                let [u, v] = ends_of(piece).map(|node| {
                    if index[node] == usize::MAX {
                        index[node] = n_nodes;
                        n_nodes += 1;
                    }
                    index[node]
                });
                edges.push([u, v]);
                lengths.push(path_length(g, piece));
            }
        }
        Self { adj: Csr::from_edges(n_nodes, &edges), lengths }
    }
}

fn ends(branch: &[usize]) -> (usize, usize) {
    let [a, b] = ends_of(branch);
    (a, b)
}

fn ends_of(path: &[usize]) -> [usize; 2] {
    [path[0], path[path.len() - 1]]
}

/// Cuts a branch as karstnet's `_split_branches` does (`parallel`: its end pair is shared).
fn pieces(branch: &[usize], parallel: bool) -> Vec<&[usize]> {
    let n = branch.len();
    if is_loop(branch) {
        let k = n / 3;
        vec![&branch[..=k], &branch[k..=2 * k], &branch[2 * k..]]
    } else if parallel && n > 2 {
        vec![&branch[..=n / 2], &branch[n / 2..]]
    } else {
        vec![branch]
    }
}

/// Length along a node path of the full graph.
fn path_length(g: &FullGraph, path: &[usize]) -> f64 {
    path.windows(2).map(|w| distance(&g.pos[w[0]], &g.pos[w[1]])).sum()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn loops_are_cut_in_three_and_parallels_in_two() {
        let loop_branch = [0, 1, 2, 3, 4, 5, 6, 0];
        let cut: Vec<_> = pieces(&loop_branch, false);
        assert_eq!(cut, vec![&[0, 1, 2][..], &[2, 3, 4], &[4, 5, 6, 0]]);
        assert_eq!(pieces(&[0, 1, 2, 0], false).len(), 3);
        assert_eq!(pieces(&[7, 1, 2, 3, 8], true), vec![&[7, 1, 2][..], &[2, 3, 8]]);
        assert_eq!(pieces(&[7, 1, 2, 8], true), vec![&[7, 1, 2][..], &[2, 8]]);
        assert_eq!(pieces(&[7, 8], true), vec![&[7, 8][..]]);
        assert_eq!(pieces(&[7, 1, 2, 8], false), vec![&[7, 1, 2, 8][..]]);
    }
}
