//! Topological metrics of the reduced graph, unweighted unless stated (spec §3 "Topology" and the
//! `basic_analysis()` counts): degree statistics, degree correlation, component-weighted average
//! shortest path length, central point dominance, Howard's α, β, γ and the connectivity degree DC
//! of Collon et al. 2017 (not computed by karstnet itself).

use crate::geometry::{coefficient_of_variation, mean};
use crate::graph::Csr;

/// Degree distribution of the reduced graph.
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct DegreeStats {
    pub(crate) mean: f64,
    pub(crate) cv: f64,
    /// Number of nodes of degree 1, 2, 3 and > 3.
    pub(crate) counts: [usize; 4],
    pub(crate) max: usize,
}

impl DegreeStats {
    pub(crate) fn of(adj: &Csr) -> Self {
        let degrees: Vec<usize> = (0..adj.n_nodes()).map(|v| adj.degree(v)).collect();
        let as_f64: Vec<f64> = degrees.iter().map(|&d| d as f64).collect();
        let mut counts = [0; 4];
        for &d in &degrees {
            if let Some(class) = d.checked_sub(1) {
                counts[class.min(3)] += 1;
            }
        }
        Self {
            mean: mean(&as_f64),
            cv: coefficient_of_variation(&as_f64),
            counts,
            max: degrees.iter().copied().max().unwrap_or(0),
        }
    }
}

/// Newman's degree assortativity (`nx.degree_pearson_correlation_coefficient`): the Pearson
/// correlation of the degree pairs (k_u, k_v) and (k_v, k_u) over all edges; 1 when every node
/// has the same degree (`cv_degree == 0`), as karstnet does.
pub(crate) fn degree_correlation(adj: &Csr, cv_degree: f64) -> f64 {
    if cv_degree == 0.0 {
        return 1.0;
    }
    let pairs: Vec<[f64; 2]> = (0..adj.n_nodes())
        .flat_map(|u| {
            let ku = adj.degree(u) as f64;
            adj.neighbors(u).iter().map(move |&v| [ku, adj.degree(v) as f64])
        })
        .collect();
    let m = pairs.iter().map(|p| p[0]).sum::<f64>() / pairs.len() as f64;
    let covariance: f64 = pairs.iter().map(|p| (p[0] - m) * (p[1] - m)).sum();
    let variance: f64 = pairs.iter().map(|p| (p[0] - m) * (p[0] - m)).sum();
    covariance / variance
}

/// karstnet's `average_SPL`: per component c of n_c nodes the mean distance over ordered pairs
/// `Σ_s per_source[s] / (n_c (n_c − 1))` (0 for a single node), averaged with weights n_c / N.
pub(crate) fn component_weighted_aspl(adj: &Csr, per_source: &[f64]) -> f64 {
    let (component, n_components) = adj.components();
    let mut sizes = vec![0usize; n_components];
    let mut sums = vec![0.0; n_components];
    for (&c, &s) in component.iter().zip(per_source) {
        sizes[c] += 1;
        sums[c] += s;
    }
    let weighted: f64 = sizes
        .iter()
        .zip(&sums)
        .filter(|(n, _)| **n > 1)
        .map(|(&n, &sum)| n as f64 * (sum / (n as f64 * (n - 1) as f64)))
        .sum();
    weighted / adj.n_nodes() as f64
}

/// Central point dominance `Σ_v (max b − b_v) / (N − 1)`, with betweenness normalised by
/// `(N − 1)(N − 2)` (networkx's normalisation, skipped when N ≤ 2).
pub(crate) fn central_point_dominance(raw_betweenness: &[f64]) -> f64 {
    let n = raw_betweenness.len() as f64;
    let scale = if n > 2.0 { 1.0 / ((n - 1.0) * (n - 2.0)) } else { 1.0 };
    let b: Vec<f64> = raw_betweenness.iter().map(|x| x * scale).collect();
    let max = b.iter().copied().fold(f64::NEG_INFINITY, f64::max);
    b.iter().map(|x| max - x).sum::<f64>() / (n - 1.0)
}

/// Howard's (1970) parameters on the reduced graph, all nodes included.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Howard {
    pub(crate) alpha: f64,
    pub(crate) beta: f64,
    pub(crate) gamma: f64,
}

impl Howard {
    /// From N nodes, S edges and the number of independent cycles S − N + p.
    pub(crate) fn new(n_nodes: usize, n_edges: usize, n_cycles: usize) -> Self {
        let (n, s) = (n_nodes as f64, n_edges as f64);
        Self { alpha: n_cycles as f64 / (2.0 * n - 5.0), beta: s / n, gamma: s / (3.0 * (n - 2.0)) }
    }

    /// Connectivity degree DC (%) of Collon et al. 2017.
    pub(crate) fn connectivity_degree(&self) -> f64 {
        100.0 * (self.alpha / 0.25 + (self.beta - 1.0) / 0.5 + (self.gamma - 0.33) / 0.17) / 3.0
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn star_degrees_and_correlation() {
        let star = Csr::from_edges(4, &[[0, 1], [0, 2], [0, 3]]);
        let d = DegreeStats::of(&star);
        assert_eq!((d.mean, d.counts, d.max), (1.5, [3, 0, 1, 0], 3));
        assert!((degree_correlation(&star, d.cv) + 1.0).abs() < 1e-15);
    }

    #[test]
    fn regular_graph_correlation_is_one() {
        let cycle = Csr::from_edges(3, &[[0, 1], [1, 2], [2, 0]]);
        assert_eq!(degree_correlation(&cycle, DegreeStats::of(&cycle).cv), 1.0);
    }

    #[test]
    fn aspl_weights_components_by_size() {
        // Path of 3 nodes (SPL 8/6) and a single edge (SPL 1): (3·4/3 + 2·1) / 5.
        let adj = Csr::from_edges(5, &[[0, 1], [1, 2], [3, 4]]);
        let aspl = component_weighted_aspl(&adj, &[3.0, 2.0, 3.0, 1.0, 1.0]);
        assert!((aspl - 6.0 / 5.0).abs() < 1e-15);
    }

    #[test]
    fn cpd_of_a_star_is_one() {
        // Centre lies on all 6 ordered leaf pairs: b = 6 / (3·2) = 1.
        assert!((central_point_dominance(&[6.0, 0.0, 0.0, 0.0]) - 1.0).abs() < 1e-15);
        assert_eq!(central_point_dominance(&[0.0, 0.0]), 0.0);
    }
}
