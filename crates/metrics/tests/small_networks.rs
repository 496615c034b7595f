//! Hand-made networks with answers worked out from the spec: the tricky rules of branch
//! extraction (§1), graph reduction (§2) and the metrics (§3).

mod common;

use karst_metrics::{Metrics, Network, characterize};

fn metrics(nodes: &[[f64; 3]], links: &[[usize; 2]]) -> Metrics {
    characterize(&Network { nodes: nodes.to_vec(), links: links.to_vec() }).expect("valid network")
}

fn assert_close(actual: f64, expected: f64, what: &str) {
    assert!(common::close(actual, expected, 1e-14), "{what}: {actual} != {expected}");
}

#[test]
fn single_edge() {
    let m = metrics(&[[0.0; 3], [3.0, 4.0, 12.0]], &[[0, 1]]);
    assert_eq!((m.n_branches, m.n_nodes_simpl, m.n_edges_simpl, m.n_cycles), (1, 2, 1, 0));
    assert_close(m.mean_length, 13.0, "mean length");
    assert_eq!((m.cv_length, m.length_entropy, m.orientation_entropy), (0.0, 0.0, 0.0));
    assert_close(m.tortuosity, 1.0, "tortuosity");
    assert_eq!((m.aspl, m.cpd, m.mean_degree, m.cv_degree), (1.0, 0.0, 1.0, 0.0));
    assert_eq!(m.correlation_vertex_degree, 1.0, "equal degrees give 1 by convention");
    assert_eq!(m.aspl_length_weighted, 13.0);
    // Howard's γ = S / (3 (N − 2)) is undefined for N = 2.
    assert!(m.howard_gamma.is_infinite() && m.connectivity_degree.is_infinite());
}

#[test]
fn star_with_a_zero_length_arm_and_bin_edges() {
    // Arms of length 1 (E), 2 (N), 4 (W), 10 (azimuth 36.87°) and 0 (leaf on the centre).
    let nodes = [[0.0; 3], [1.0, 0.0, 0.0], [0.0, 2.0, 0.0], [-4.0, 0.0, 0.0], [6.0, 8.0, 0.0], [0.0; 3]];
    let m = metrics(&nodes, &[[0, 1], [0, 2], [0, 3], [0, 4], [0, 5]]);
    assert_eq!(m.n_branches, 5);
    assert_close(m.mean_length, 17.0 / 5.0, "mean length includes the zero-length branch");
    assert_close(m.total_length, 17.0, "total length");
    // Normalised non-zero lengths 10, 20, 40, 100: bins 1, 2, 4 and 9 (100 is in the last bin).
    assert_close(m.length_entropy, 4f64.ln() / 10f64.ln(), "length entropy");
    // The zero-length arm has coincident ends: excluded from the tortuosity.
    assert_close(m.tortuosity, 1.0, "tortuosity");
    // Azimuth weights by projected length: 90° (E, W) 1 + 4, 0° (N) 2, 36.87° 10.
    let h: f64 = [5.0f64, 2.0, 10.0].iter().map(|w| -(w / 17.0) * (w / 17.0).ln()).sum();
    assert_close(m.orientation_entropy, h / 18f64.ln(), "orientation entropy");
    // Star of 6 nodes: the centre is on all 20 ordered leaf pairs, b = 20 / (5·4) = 1.
    assert_close(m.cpd, 1.0, "cpd");
    assert_close(m.aspl, (10.0 * 1.0 + 20.0 * 2.0) / 30.0, "aspl");
    assert_close(m.correlation_vertex_degree, -1.0, "correlation");
    assert_eq!((m.simpl_count_deg1, m.simpl_count_deg_over3, m.simpl_max_degree), (5, 1, 5));
}

#[test]
fn isolated_cycle_is_one_looping_branch_cut_in_three() {
    let m = metrics(
        &[[0.0; 3], [1.0, 0.0, 0.0], [1.0, 1.0, 0.0], [0.0, 1.0, 0.0]],
        &[[0, 1], [1, 2], [2, 3], [3, 0]],
    );
    assert_eq!((m.n_branches, m.n_looping_branches), (1, 1));
    assert!(m.tortuosity.is_nan(), "every branch loops");
    // Branch [s, a, b, c, s] (5 nodes, k = 1) → pieces of 1, 1 and 2 edges: a triangle.
    assert_eq!((m.n_nodes_simpl, m.n_edges_simpl, m.n_cycles), (3, 3, 1));
    assert_eq!((m.mean_degree, m.cv_degree, m.correlation_vertex_degree), (2.0, 0.0, 1.0));
    assert_eq!((m.aspl, m.cpd), (1.0, 0.0));
    // Piece lengths 1, 1, 2: distances 1, 1, 2 → 8 / 6 over ordered pairs.
    assert_close(m.aspl_length_weighted, 4.0 / 3.0, "aspl length weighted");
    let json = serde_json::to_string(&m).expect("serialisable");
    assert!(json.contains("\"tortuosity\":null"));
}

#[test]
fn loop_on_a_junction_is_cut_in_three() {
    // Tail 5-0 and loop 0-1-2-3-4-0: branch [0,1,2,3,4,0] has 6 nodes, k = 2 → cuts at 2 and 4.
    let nodes =
        [[0.0; 3], [1.0, 0.0, 0.0], [2.0, 1.0, 0.0], [1.0, 2.0, 0.0], [0.0, 1.0, 0.0], [-1.0, 0.0, 0.0]];
    let m = metrics(&nodes, &[[5, 0], [0, 1], [1, 2], [2, 3], [3, 4], [4, 0]]);
    assert_eq!((m.n_branches, m.n_looping_branches), (2, 1));
    assert_eq!((m.n_nodes_simpl, m.n_edges_simpl, m.n_cycles), (4, 4, 1));
    assert_eq!((m.simpl_count_deg1, m.simpl_count_deg2, m.simpl_count_deg3), (1, 2, 1));
    assert_close(m.tortuosity, 1.0, "the loop is excluded");
}

#[test]
fn parallel_conduits_are_cut_in_two() {
    // Junctions A=0 and B=1 with tails 2 and 3; conduits 0-4-5-1 (cut at 5) and 0-6-7-8-1 (cut at 7).
    let nodes: Vec<[f64; 3]> = (0..9).map(|i| [i as f64, (i * i % 7) as f64, 0.0]).collect();
    let links = [[0, 2], [1, 3], [0, 4], [4, 5], [5, 1], [0, 6], [6, 7], [7, 8], [8, 1]];
    let m = metrics(&nodes, &links);
    assert_eq!((m.n_branches, m.n_looping_branches), (4, 0));
    assert_eq!((m.n_nodes_simpl, m.n_edges_simpl, m.n_cycles), (6, 6, 1));
    assert_eq!((m.simpl_count_deg1, m.simpl_count_deg2, m.simpl_count_deg3), (2, 2, 2));
    assert_close(m.howard_beta, 1.0, "beta");

    // A direct link between the junctions stays whole; the other conduit is cut.
    let links = [[0, 2], [1, 3], [0, 1], [0, 4], [4, 5], [5, 1]];
    let m = metrics(&nodes, &links);
    assert_eq!((m.n_nodes_simpl, m.n_edges_simpl, m.n_cycles), (5, 5, 1));
}

#[test]
fn two_components_weight_aspl_by_size_and_share_the_betweenness_normalisation() {
    // Component 1: a 3-node path, reduced to one edge. Component 2: a star with 3 leaves.
    let nodes: Vec<[f64; 3]> =
        [[0.0, 0.0], [1.0, 0.0], [2.0, 0.5], [10.0, 0.0], [11.0, 0.0], [10.0, 1.0], [9.0, 0.0]]
            .iter()
            .map(|&[x, y]| [x, y, 0.0])
            .collect();
    let m = metrics(&nodes, &[[0, 1], [1, 2], [3, 4], [3, 5], [3, 6]]);
    assert_eq!((m.n_components_full, m.n_components_simpl, m.n_nodes_simpl), (2, 2, 6));
    // SPL 1 on 2 nodes and 1.5 on 4 nodes: (2·1 + 4·1.5) / 6.
    assert_close(m.aspl, 8.0 / 6.0, "aspl");
    // Star centre: 6 ordered leaf pairs / ((6−1)(6−2)) = 0.3; cpd = 5 · 0.3 / 5.
    assert_close(m.cpd, 0.3, "cpd");
    assert_eq!(m.n_cycles, 0);
}

#[test]
fn duplicate_and_reversed_links_collapse() {
    let nodes = [[0.0; 3], [1.0, 0.0, 0.0], [1.0, 1.0, 0.0], [5.0, 5.0, 5.0]];
    let once = metrics(&nodes, &[[0, 1], [1, 2]]);
    let repeated = metrics(&nodes, &[[0, 1], [1, 0], [1, 2], [0, 1], [2, 1]]);
    assert_eq!(once, repeated);
    assert_eq!(once.n_nodes_full, 3, "node 3 is in no link and ignored");
}
