//! Paris et al. 2021 mode (§5.1): the γ-skeleton of the key points.
//!
//! 1. The anisotropic distance between every pair of key points is the cost of the least-cost
//!    path in the cost graph, one Dijkstra per key point. Costs may be directed; the distance
//!    of a pair is the mean of its two directions, so that the rule below is symmetric.
//! 2. The γ-skeleton rule keeps a–b unless some key point k has d(a,k)^γ + d(k,b)^γ < d(a,b)^γ.
//!    γ = 2 gives a Gabriel-like graph, γ → ∞ the relative neighbourhood graph and small γ denser
//!    networks. The rule only depends on the ratios d(a,k)/d(a,b) and d(k,b)/d(a,b), which are
//!    both below 1 when a pair is removed; raising them to a larger power only shrinks the sum,
//!    so a smaller γ never removes a pair that a larger γ keeps (tested).
//! 3. Pairs of `skeleton.forced_links` are always kept; every kept pair contributes the
//!    least-cost path from its first to its second key point (scene order).
//! 4. Cohesion (KarstNSim's P_red, here in gamma mode too): a conduit drains the rock around
//!    it and captures the flow paths that come near (conduit piracy), so passages merge into
//!    trunks instead of running side by side to meet at one key point. With
//!    `skeleton.cohesion_vadose` / `cohesion_phreatic` below 1 the kept pairs are drawn
//!    shortest first (the shortest connections break through first), each on costs where the
//!    edges already used cost P_red times less. Junctions then sit where a path leaves a
//!    trunk, and key points are not hubs of many parallel passages.
//!
//! Dead-end key points are not vertices of the γ-skeleton: they join the finished network once.
//! The routes (sink → spring) that hydrology needs are then drawn inside the network: the
//! least-cost path along its links, springs chosen by the connectivity matrix.

use glam::DVec3;
use rayon::prelude::*;

use karst_costgraph::CostGraph;
use karst_sampling::Samples;
use karst_scene::KeyPointKind;

use crate::Route;
use crate::error::SkeletonError;
use crate::modes::karstnsim::mark_used;
use crate::network::assemble::NetworkBuilder;
use crate::network::nodes::is_phreatic;
use crate::route::edge_set::EdgeSet;
use crate::route::ends::{End, chosen_springs, ends, sample_of, sinks_in_order};
use crate::route::search::{Tree, ZonedCohesive, astar, dijkstra, min_cost_per_metre};
use crate::view::SkeletonView;

/// The pairs (i, j), i < j, of the γ-skeleton of the distance matrix `d` (symmetric, zero
/// diagonal); pairs at infinite distance are never kept.
pub fn gamma_skeleton(d: &[Vec<f64>], gamma: f64) -> Vec<(usize, usize)> {
    let n = d.len();
    let mut kept = Vec::new();
    for a in 0..n {
        for b in a + 1..n {
            let ab = d[a][b];
            if !ab.is_finite() {
                continue;
            }
            let blocked = (0..n)
                .any(|k| k != a && k != b && (d[a][k] / ab).powf(gamma) + (d[k][b] / ab).powf(gamma) < 1.0);
            if !blocked {
                kept.push((a, b));
            }
        }
    }
    kept
}

/// Adds the γ-skeleton's paths to `network`; returns the routes of the sinks along it.
pub fn network(
    view: &SkeletonView,
    samples: &Samples,
    graph: &CostGraph,
    network: &mut NetworkBuilder,
) -> Result<Vec<(Route, Vec<usize>)>, SkeletonError> {
    let keypoints: Vec<End> = view
        .keypoints
        .iter()
        .enumerate()
        .filter(|(_, k)| k.kind != KeyPointKind::DeadEnd)
        .map(|(i, k)| End { row: i, keypoint: i, name: &k.name })
        .collect();
    let sources = keypoints.iter().map(|k| sample_of(samples, k)).collect::<Result<Vec<_>, _>>()?;
    let trees: Vec<Tree> = sources.par_iter().map(|&s| dijkstra(graph, s, &sources)).collect();
    let n = keypoints.len();
    let mut d = vec![vec![0.0; n]; n];
    for a in 0..n {
        for b in 0..n {
            if a != b {
                d[a][b] = 0.5 * (trees[a].cost(sources[b]) + trees[b].cost(sources[a]));
            }
        }
    }
    check_reachable(&d, &keypoints)?;
    let mut pairs = gamma_skeleton(&d, view.skeleton.gamma);
    for [a, b] in &view.skeleton.forced_links {
        let index = |name: &str| keypoints.iter().position(|k| k.name == name).expect("validated link");
        let (a, b) = (index(a), index(b));
        pairs.push((a.min(b), a.max(b)));
    }
    pairs.sort_unstable();
    pairs.dedup();
    draw_paths(view, samples, graph, &d, &sources, &trees, &pairs, network);
    routes_along(view, samples, graph, network)
}

/// Adds the least-cost path of every kept pair to `network`. Without cohesion (P_red = 1 in both
/// zones) they are the paths of the distance trees. With cohesion the pairs are drawn shortest
/// first, each on costs where the edges of the paths drawn before it cost P_red times less
/// (`skeleton.cohesion_vadose` out of a vadose sample, `skeleton.cohesion_phreatic` out of a
/// phreatic one), so that a later path follows an existing conduit as long as it leads its
/// way, and leaves it at a junction.
#[allow(clippy::too_many_arguments)]
fn draw_paths(
    view: &SkeletonView,
    samples: &Samples,
    graph: &CostGraph,
    d: &[Vec<f64>],
    sources: &[usize],
    trees: &[Tree],
    pairs: &[(usize, usize)],
    network: &mut NetworkBuilder,
) {
    let p = view.skeleton;
    if p.cohesion_vadose >= 1.0 && p.cohesion_phreatic >= 1.0 {
        for &(a, b) in pairs {
            network.add_path(&trees[a].path(sources[b]).expect("finite distance"));
        }
        return;
    }
    let mut order = pairs.to_vec();
    order.sort_by(|x, y| d[x.0][x.1].total_cmp(&d[y.0][y.1]).then(x.cmp(y)));
    let phreatic: Vec<bool> =
        samples.positions.iter().map(|&q| is_phreatic(view.geology, DVec3::from_array(q))).collect();
    let per_metre =
        min_cost_per_metre(graph, &samples.positions) * p.cohesion_vadose.min(p.cohesion_phreatic);
    let mut used = EdgeSet::new(graph.edge_count());
    for (a, b) in order {
        let costs = ZonedCohesive {
            base: graph,
            used: &used,
            phreatic: &phreatic,
            factors: [p.cohesion_vadose, p.cohesion_phreatic],
        };
        let tree = astar(&costs, &samples.positions, per_metre, sources[a], sources[b]);
        network.add_path(&tree.path(sources[b]).expect("finite distance"));
        mark_used(graph, &tree.edges(sources[b]), &mut used);
    }
}

/// Every key point must reach every other: name the first that cannot.
fn check_reachable(d: &[Vec<f64>], keypoints: &[End]) -> Result<(), SkeletonError> {
    for (a, row) in d.iter().enumerate() {
        if let Some(b) = row.iter().position(|c| !c.is_finite()) {
            return Err(SkeletonError::KeyPointsApart {
                a: keypoints[a].name.into(),
                b: keypoints[b].name.into(),
            });
        }
    }
    Ok(())
}

/// The route of every sink to its spring(s) along the network's links, each link costing the
/// cheaper direction of its cost-graph edge.
fn routes_along(
    view: &SkeletonView,
    samples: &Samples,
    graph: &CostGraph,
    network: &NetworkBuilder,
) -> Result<Vec<(Route, Vec<usize>)>, SkeletonError> {
    let lists = network
        .adjacency
        .iter()
        .enumerate()
        .map(|(a, next)| {
            next.iter()
                .map(|&b| (b, link_cost(graph, network.samples[a], network.samples[b as usize])))
                .collect()
        })
        .collect();
    let links = CostGraph::from_lists(lists);
    let springs = ends(view, KeyPointKind::Spring);
    let node = |end: &End| -> Result<usize, SkeletonError> {
        let sample = sample_of(samples, end)?;
        Ok(network.node_of(sample).expect("every key point is on the γ-skeleton") as usize)
    };
    let mut routes = Vec::new();
    for sink in sinks_in_order(view) {
        let from = node(&sink)?;
        let targets = springs.iter().map(&node).collect::<Result<Vec<_>, _>>()?;
        let tree = dijkstra(&links, from, &targets);
        let chosen = chosen_springs(view, &sink, &springs, &mut |t| Ok(tree.cost(node(t)?)))?;
        for spring in chosen {
            let to = node(&spring)?;
            let path = tree.path(to).expect("chosen springs are reachable");
            let route = Route {
                sink: sink.name.to_string(),
                spring: spring.name.to_string(),
                weight: view.keypoints[sink.keypoint].weight,
                nodes: Vec::new(),
                cost: tree.cost(to),
            };
            routes.push((route, path.iter().map(|&i| network.samples[i] as usize).collect()));
        }
    }
    Ok(routes)
}

/// Cost of the link between samples a and b: the cheaper of its directed edges.
fn link_cost(graph: &CostGraph, a: u32, b: u32) -> f32 {
    let one = |u: u32, v: u32| graph.out_edges(u as usize).find(|(t, _)| *t == v as usize).map(|(_, c)| c);
    match (one(a, b), one(b, a)) {
        (Some(x), Some(y)) => x.min(y),
        (Some(x), None) | (None, Some(x)) => x,
        (None, None) => f32::INFINITY,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use karst_scene::rng::Random;

    fn random_distances(seed: u64, n: usize) -> Vec<Vec<f64>> {
        let mut rng = Random::stream(seed, "test", "gamma");
        let p: Vec<[f64; 3]> = (0..n).map(|_| [rng.uniform(), rng.uniform(), rng.uniform() * 0.3]).collect();
        let mut d = vec![vec![0.0; n]; n];
        for a in 0..n {
            for b in a + 1..n {
                // Anisotropic: vertical distances cost three times more.
                let [dx, dy, dz] = [0, 1, 2].map(|i| p[a][i] - p[b][i]);
                let c = (dx * dx + dy * dy + 9.0 * dz * dz).sqrt() * rng.range(1.0, 1.3);
                d[a][b] = c;
                d[b][a] = c;
            }
        }
        d
    }

    #[test]
    fn smaller_gamma_never_removes_a_pair_a_larger_gamma_keeps() {
        let gammas = [0.3, 0.8, 1.0, 1.5, 2.0, 3.0, 8.0, 40.0];
        for seed in 0..10 {
            let d = random_distances(seed, 30);
            let skeletons: Vec<_> = gammas.iter().map(|&g| gamma_skeleton(&d, g)).collect();
            for w in skeletons.windows(2) {
                assert!(w[1].iter().all(|p| w[0].contains(p)), "seed {seed}");
            }
            assert!(skeletons[0].len() > skeletons[gammas.len() - 1].len(), "seed {seed}");
        }
    }

    #[test]
    fn large_gamma_gives_the_relative_neighbourhood_graph() {
        let d = random_distances(3, 25);
        let rng: Vec<(usize, usize)> = (0..25)
            .flat_map(|a| (a + 1..25).map(move |b| (a, b)))
            .filter(|&(a, b)| !(0..25).any(|k| k != a && k != b && d[a][k].max(d[k][b]) < d[a][b]))
            .collect();
        assert_eq!(gamma_skeleton(&d, 200.0), rng);
    }

    #[test]
    fn the_skeleton_is_connected() {
        for gamma in [0.5, 2.0, 50.0] {
            let d = random_distances(7, 40);
            let pairs = gamma_skeleton(&d, gamma);
            let mut reached = [false; 40];
            reached[0] = true;
            for _ in 0..40 {
                for &(a, b) in &pairs {
                    if reached[a] || reached[b] {
                        reached[a] = true;
                        reached[b] = true;
                    }
                }
            }
            assert!(reached.iter().all(|r| *r), "γ = {gamma}");
        }
    }
}
