//! The result record and the pipeline that fills it (spec §0–§3).
//!
//! [`Metrics`] serialises with karstnet's key names (those of `expected-metrics.json`); undefined
//! values (NaN, ±∞) are written as JSON `null`. Every metric is independent of node numbering and
//! of link order and direction except "aspl length weighted", which inherits karstnet's
//! dependence on them through the cut positions of loops and parallel conduits (see `reduced`).

use serde::{Deserialize, Serialize};

use crate::branches::{self, is_loop};
use crate::geometry::{self, Bins};
use crate::graph::FullGraph;
use crate::network::{MetricsError, Network};
use crate::reduced::Reduced;
use crate::shortest_paths::all_pairs;
use crate::topology::{self, DegreeStats, Howard};

/// Every statistic of one network, named as karstnet names it.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Metrics {
    /// Mean branch length.
    #[serde(rename = "mean length", with = "crate::nullable")]
    pub mean_length: f64,
    /// Coefficient of variation of branch lengths (sample std / mean).
    #[serde(rename = "cv length", with = "crate::nullable")]
    pub cv_length: f64,
    /// Entropy of branch lengths, 10 bins.
    #[serde(rename = "length entropy", with = "crate::nullable")]
    pub length_entropy: f64,
    /// Mean tortuosity of the non-looping branches (NaN if every branch loops).
    #[serde(rename = "tortuosity", with = "crate::nullable")]
    pub tortuosity: f64,
    /// Entropy of conduit azimuths weighted by projected length, 18 bins.
    #[serde(rename = "orientation entropy", with = "crate::nullable")]
    pub orientation_entropy: f64,
    /// Average shortest path length (hops) of the reduced graph, component-weighted.
    #[serde(rename = "aspl", with = "crate::nullable")]
    pub aspl: f64,
    /// Central point dominance of the reduced graph.
    #[serde(rename = "cpd", with = "crate::nullable")]
    pub cpd: f64,
    /// Mean degree of the reduced graph.
    #[serde(rename = "mean degree", with = "crate::nullable")]
    pub mean_degree: f64,
    /// Coefficient of variation of the reduced graph's degrees.
    #[serde(rename = "cv degree", with = "crate::nullable")]
    pub cv_degree: f64,
    /// Degree assortativity of the reduced graph (1 if all degrees are equal).
    #[serde(rename = "correlation vertex degree", with = "crate::nullable")]
    pub correlation_vertex_degree: f64,
    pub n_nodes_full: usize,
    pub n_edges_full: usize,
    pub n_components_full: usize,
    pub n_nodes_simpl: usize,
    pub n_edges_simpl: usize,
    pub n_components_simpl: usize,
    /// Independent cycles of the reduced graph, S − N + p.
    pub n_cycles: usize,
    pub n_branches: usize,
    pub n_looping_branches: usize,
    /// Sum of all branch lengths.
    #[serde(with = "crate::nullable")]
    pub total_length: f64,
    /// Length entropy with Sturges' number of bins.
    #[serde(rename = "length entropy sturges", with = "crate::nullable")]
    pub length_entropy_sturges: f64,
    /// Orientation entropy with Sturges' number of bins.
    #[serde(rename = "orientation entropy sturges", with = "crate::nullable")]
    pub orientation_entropy_sturges: f64,
    /// karstnet's `average_SPL(dist_weight=True)`: aspl along conduit lengths.
    #[serde(rename = "aspl length weighted", with = "crate::nullable")]
    pub aspl_length_weighted: f64,
    #[serde(rename = "howard alpha", with = "crate::nullable")]
    pub howard_alpha: f64,
    #[serde(rename = "howard beta", with = "crate::nullable")]
    pub howard_beta: f64,
    #[serde(rename = "howard gamma", with = "crate::nullable")]
    pub howard_gamma: f64,
    /// Connectivity degree DC of Collon et al. 2017, in percent.
    #[serde(rename = "connectivity degree DC (%)", with = "crate::nullable")]
    pub connectivity_degree: f64,
    #[serde(rename = "simpl count deg1")]
    pub simpl_count_deg1: usize,
    #[serde(rename = "simpl count deg2")]
    pub simpl_count_deg2: usize,
    #[serde(rename = "simpl count deg3")]
    pub simpl_count_deg3: usize,
    #[serde(rename = "simpl count deg>3")]
    pub simpl_count_deg_over3: usize,
    #[serde(rename = "simpl frac deg1", with = "crate::nullable")]
    pub simpl_frac_deg1: f64,
    #[serde(rename = "simpl frac deg2", with = "crate::nullable")]
    pub simpl_frac_deg2: f64,
    #[serde(rename = "simpl frac deg3", with = "crate::nullable")]
    pub simpl_frac_deg3: f64,
    #[serde(rename = "simpl frac deg>3", with = "crate::nullable")]
    pub simpl_frac_deg_over3: f64,
    #[serde(rename = "simpl max degree")]
    pub simpl_max_degree: usize,
}

impl Metrics {
    /// Every metric as `(karstnet key, value)`, in serialisation order (counts as `f64`).
    pub fn to_pairs(&self) -> Vec<(&'static str, f64)> {
        let count = |c: usize| c as f64;
        vec![
            ("mean length", self.mean_length),
            ("cv length", self.cv_length),
            ("length entropy", self.length_entropy),
            ("tortuosity", self.tortuosity),
            ("orientation entropy", self.orientation_entropy),
            ("aspl", self.aspl),
            ("cpd", self.cpd),
            ("mean degree", self.mean_degree),
            ("cv degree", self.cv_degree),
            ("correlation vertex degree", self.correlation_vertex_degree),
            ("n_nodes_full", count(self.n_nodes_full)),
            ("n_edges_full", count(self.n_edges_full)),
            ("n_components_full", count(self.n_components_full)),
            ("n_nodes_simpl", count(self.n_nodes_simpl)),
            ("n_edges_simpl", count(self.n_edges_simpl)),
            ("n_components_simpl", count(self.n_components_simpl)),
            ("n_cycles", count(self.n_cycles)),
            ("n_branches", count(self.n_branches)),
            ("n_looping_branches", count(self.n_looping_branches)),
            ("total_length", self.total_length),
            ("length entropy sturges", self.length_entropy_sturges),
            ("orientation entropy sturges", self.orientation_entropy_sturges),
            ("aspl length weighted", self.aspl_length_weighted),
            ("howard alpha", self.howard_alpha),
            ("howard beta", self.howard_beta),
            ("howard gamma", self.howard_gamma),
            ("connectivity degree DC (%)", self.connectivity_degree),
            ("simpl count deg1", count(self.simpl_count_deg1)),
            ("simpl count deg2", count(self.simpl_count_deg2)),
            ("simpl count deg3", count(self.simpl_count_deg3)),
            ("simpl count deg>3", count(self.simpl_count_deg_over3)),
            ("simpl frac deg1", self.simpl_frac_deg1),
            ("simpl frac deg2", self.simpl_frac_deg2),
            ("simpl frac deg3", self.simpl_frac_deg3),
            ("simpl frac deg>3", self.simpl_frac_deg_over3),
            ("simpl max degree", count(self.simpl_max_degree)),
        ]
    }
}

/// Computes all karstnet statistics of a network (see the crate docs for the definitions).
pub fn characterize(net: &Network) -> Result<Metrics, MetricsError> {
    net.validate()?;
    let g = FullGraph::build(net);
    let branches = branches::extract(&g);
    let lengths = geometry::branch_lengths(&g, &branches);
    let reduced = Reduced::build(&g, &branches);
    let paths = all_pairs(&reduced.adj, &reduced.lengths);
    let hop_sums: Vec<f64> = paths.hop_sums.iter().map(|&h| h as f64).collect();
    let degrees = DegreeStats::of(&reduced.adj);

    let n = reduced.adj.n_nodes();
    let s = reduced.adj.n_edges();
    let p = reduced.adj.components().1;
    let n_cycles = (s + p).saturating_sub(n);
    let howard = Howard::new(n, s, n_cycles);
    let fraction = |c: usize| c as f64 / n as f64;
    let [deg1, deg2, deg3, over3] = degrees.counts;

    Ok(Metrics {
        mean_length: geometry::mean(&lengths),
        cv_length: geometry::coefficient_of_variation(&lengths),
        length_entropy: geometry::length_entropy(&lengths, Bins::Default),
        tortuosity: geometry::tortuosity(&g, &branches, &lengths),
        orientation_entropy: geometry::orientation_entropy(&g, Bins::Default),
        aspl: topology::component_weighted_aspl(&reduced.adj, &hop_sums),
        cpd: topology::central_point_dominance(&paths.betweenness),
        mean_degree: degrees.mean,
        cv_degree: degrees.cv,
        correlation_vertex_degree: topology::degree_correlation(&reduced.adj, degrees.cv),
        n_nodes_full: g.n_nodes(),
        n_edges_full: g.edges.len(),
        n_components_full: g.adj.components().1,
        n_nodes_simpl: n,
        n_edges_simpl: s,
        n_components_simpl: p,
        n_cycles,
        n_branches: branches.len(),
        n_looping_branches: branches.iter().filter(|b| is_loop(b)).count(),
        total_length: lengths.iter().sum(),
        length_entropy_sturges: geometry::length_entropy(&lengths, Bins::Sturges),
        orientation_entropy_sturges: geometry::orientation_entropy(&g, Bins::Sturges),
        aspl_length_weighted: topology::component_weighted_aspl(&reduced.adj, &paths.length_sums),
        howard_alpha: howard.alpha,
        howard_beta: howard.beta,
        howard_gamma: howard.gamma,
        connectivity_degree: howard.connectivity_degree(),
        simpl_count_deg1: deg1,
        simpl_count_deg2: deg2,
        simpl_count_deg3: deg3,
        simpl_count_deg_over3: over3,
        simpl_frac_deg1: fraction(deg1),
        simpl_frac_deg2: fraction(deg2),
        simpl_frac_deg3: fraction(deg3),
        simpl_frac_deg_over3: fraction(over3),
        simpl_max_degree: degrees.max,
    })
}

/// The distributions behind the geometric metrics, for plots.
#[derive(Debug, Clone, PartialEq)]
pub struct Distributions {
    /// Length of every branch, in karstnet's discovery order.
    pub branch_lengths: Vec<f64>,
    /// Projected conduit length per 10° azimuth class, N–S (0°–10°) first, 18 classes.
    pub azimuth_lengths: Vec<f64>,
}

/// The branch lengths and the azimuth histogram of a network.
pub fn distributions(net: &Network) -> Result<Distributions, MetricsError> {
    net.validate()?;
    let g = FullGraph::build(net);
    let branches = branches::extract(&g);
    Ok(Distributions {
        branch_lengths: geometry::branch_lengths(&g, &branches),
        azimuth_lengths: geometry::orientation_histogram(&g),
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn single_edge() -> Metrics {
        let net = Network { nodes: vec![[0.0; 3], [3.0, 4.0, 0.0]], links: vec![[0, 1]] };
        characterize(&net).expect("valid network")
    }

    #[test]
    fn pairs_follow_the_serialised_keys_and_values() {
        let m = single_edge();
        let json = serde_json::to_value(&m).expect("serialisable");
        let object = json.as_object().expect("an object");
        let pairs = m.to_pairs();
        assert_eq!(object.len(), pairs.len());
        for (key, value) in pairs {
            match object[key].as_f64() {
                Some(v) => assert_eq!(v, value, "{key}"),
                None => assert!(!value.is_finite(), "{key}"),
            }
        }
    }

    #[test]
    fn undefined_values_round_trip_through_null() {
        let m = single_edge();
        // One reduced edge: N = 2, so γ = S / (3 (N − 2)) is infinite.
        assert!(m.howard_gamma.is_infinite());
        let text = serde_json::to_string(&m).expect("serialisable");
        assert!(text.contains("\"howard gamma\":null"));
        let back: Metrics = serde_json::from_str(&text).expect("deserialisable");
        assert!(back.howard_gamma.is_nan());
        assert_eq!(back.mean_length, 5.0);
    }

    #[test]
    fn distributions_of_an_l_shaped_pair() {
        // A 3-4-5 edge (azimuth ~36.9°) and an E–W edge of 2 from a junction of degree 2: one branch.
        let net =
            Network { nodes: vec![[0.0; 3], [3.0, 4.0, 0.0], [5.0, 4.0, 0.0]], links: vec![[0, 1], [1, 2]] };
        let d = distributions(&net).expect("valid network");
        assert_eq!(d.branch_lengths, vec![7.0]);
        assert_eq!(d.azimuth_lengths.len(), 18);
        assert_eq!(d.azimuth_lengths[3], 5.0);
        assert_eq!(d.azimuth_lengths[9], 2.0);
        assert_eq!(d.azimuth_lengths.iter().sum::<f64>(), 7.0);
    }
}
