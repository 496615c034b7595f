//! The "Done when" of the cost graph: least-cost paths through graphs built on seeded random
//! point clouds behave as the geology says.

use karst_costgraph::CostgraphView;
use karst_scene::SceneView;
use std::collections::BinaryHeap;
use std::path::Path;

use glam::DVec3;
use karst_costgraph::{CostGraph, Costing, build_points};
use karst_scene::Scene;
use karst_scene::rng::Random;

/// A scene over `[0, size]` with `extra` appended (geology, [costgraph]).
fn scene(size: [f64; 3], extra: &str) -> Scene {
    let text = format!(
        r#"
name = "t"
[domain]
min = [0, 0, 0]
max = [{}, {}, {}]
[terrain]
kind = "plane"
elevation = {}
[[geology.water_tables]]
name = "wt"
elevation = -1000
[[keypoints]]
name = "a"
kind = "sink"
position = [1, 1, 1]
[[keypoints]]
name = "s"
kind = "spring"
position = [2, 2, 1]
water_table = "wt"
{extra}
"#,
        size[0], size[1], size[2], size[2]
    );
    Scene::parse(&text, Path::new("t.toml")).unwrap()
}

/// `n` uniform random points in the box `[0, size]`, the first two given.
fn cloud(n: usize, size: [f64; 3], first: [[f64; 3]; 2], seed: u64) -> Vec<[f64; 3]> {
    let mut rng = Random::stream(seed, "costgraph-test", "cloud");
    let mut points = first.to_vec();
    points
        .extend((2..n).map(|_| [rng.range(0.0, size[0]), rng.range(0.0, size[1]), rng.range(0.0, size[2])]));
    points
}

/// The cost graph of `points` under `scene`, every row costed.
fn costed(scene: &Scene, points: &[[f64; 3]]) -> CostGraph {
    let graph = build_points(&CostgraphView::of(scene), points).unwrap();
    graph.cost_from(&CostgraphView::of(scene), points, Costing::Every).unwrap();
    graph
}

/// Every edge's cost in every set, row by row.
fn every_cost(graph: &CostGraph) -> Vec<f32> {
    (0..graph.cost_sets.len())
        .flat_map(|set| (0..graph.node_count()).flat_map(move |node| graph.row_costs(set, node).to_vec()))
        .collect()
}

/// Least-cost path 0 → 1 in cost set `set`, as node indices.
fn path(graph: &CostGraph, set: usize) -> Vec<usize> {
    let n = graph.node_count();
    let mut cost = vec![f64::INFINITY; n];
    let mut previous = vec![usize::MAX; n];
    let mut heap = BinaryHeap::new();
    cost[0] = 0.0;
    heap.push(std::cmp::Reverse((0f64.to_bits(), 0usize)));
    while let Some(std::cmp::Reverse((bits, u))) = heap.pop() {
        if f64::from_bits(bits) > cost[u] {
            continue;
        }
        if u == 1 {
            break;
        }
        for (v, c) in graph.out_edges_in(set, u) {
            let through = cost[u] + f64::from(c);
            if through < cost[v] {
                cost[v] = through;
                previous[v] = u;
                heap.push(std::cmp::Reverse((through.to_bits(), v)));
            }
        }
    }
    assert!(cost[1].is_finite(), "no path");
    let mut nodes = vec![1];
    while *nodes.last().unwrap() != 0 {
        nodes.push(previous[*nodes.last().unwrap()]);
    }
    nodes.reverse();
    nodes
}

fn at(points: &[[f64; 3]], i: usize) -> DVec3 {
    DVec3::from_array(points[i])
}

fn length(points: &[[f64; 3]], nodes: &[usize]) -> f64 {
    nodes.windows(2).map(|w| at(points, w[0]).distance(at(points, w[1]))).sum()
}

#[test]
fn homogeneous_paths_are_nearly_straight() {
    let size = [100.0, 100.0, 100.0];
    let scene = scene(
        size,
        "[costgraph]\nk = 100\nalpha_inception = 0.0\nalpha_fracture = 0.0\nalpha_water_table = 0.0\nalpha_potential = 0.0",
    );
    for (seed, ends) in
        [(1, [[5.0, 5.0, 5.0], [95.0, 95.0, 95.0]]), (2, [[5.0, 50.0, 90.0], [95.0, 50.0, 10.0]])]
    {
        let points = cloud(20_000, size, ends, seed);
        let graph = costed(&scene, &points);
        let straight = at(&points, 0).distance(at(&points, 1));
        let ratio = length(&points, &path(&graph, 0)) / straight;
        eprintln!("seed {seed}: path / straight line = {ratio:.4}");
        assert!(ratio < 1.02, "seed {seed}: path is {ratio:.4} × the straight line");
    }
}

/// Fraction of the horizontal length of the path within `tolerance` degrees of one of `azimuths`.
fn fraction_along(points: &[[f64; 3]], nodes: &[usize], azimuths: &[f64], tolerance: f64) -> f64 {
    let (mut along, mut total) = (0.0, 0.0);
    for w in nodes.windows(2) {
        let d = at(points, w[1]) - at(points, w[0]);
        let horizontal = d.x.hypot(d.y);
        let azimuth = d.x.atan2(d.y).to_degrees();
        let off = |a: f64| {
            let x = (azimuth - a).rem_euclid(180.0);
            x.min(180.0 - x)
        };
        if azimuths.iter().any(|&a| off(a) <= tolerance) {
            along += horizontal;
        }
        total += horizontal;
    }
    along / total
}

#[test]
fn paths_follow_two_fracture_families() {
    let size = [200.0, 200.0, 10.0];
    let families = r#"
[[geology.fractures]]
name = "n020"
azimuth = 20.0
tolerance = 8.0
[[geology.fractures]]
name = "n110"
azimuth = 110.0
tolerance = 8.0
"#;
    let ends = [[10.0, 100.0, 5.0], [190.0, 110.0, 5.0]];
    let points = cloud(30_000, size, ends, 3);
    for model in ["karstnsim2024", "paris2021"] {
        let params = format!(
            "{families}[costgraph]\nmodel = \"{model}\"\nk = 60\nalpha_inception = 0.0\nalpha_water_table = 0.0\nalpha_potential = 0.0\nw_horizon = 0.0\nw_permeability = 0.0\nw_distance = 0.0\nw_fracture = 4.0\nalpha_fracture = 4.0"
        );
        let graph = costed(&scene(size, &params), &points);
        let nodes = path(&graph, 0);
        let within = fraction_along(&points, &nodes, &[20.0, 110.0], 8.0);
        eprintln!("{model}: {:.1} % of the horizontal length within the families", within * 100.0);
        // Uniform directions would put 2 × 16 / 180 = 18 % of the length there.
        assert!(within > 0.8, "{model}: {:.0} % of the length within the families", within * 100.0);
    }
}

#[test]
fn vadose_paths_descend() {
    let size = [100.0, 100.0, 100.0];
    let params = "[costgraph]\nk = 40\nalpha_inception = 0.0\nalpha_fracture = 0.0\nalpha_potential = 0.0";
    let scene = scene(size, params);
    let points = cloud(20_000, size, [[10.0, 50.0, 95.0], [90.0, 50.0, 5.0]], 4);
    let graph = costed(&scene, &points);
    let set = graph.cost_set_of_water_table("wt").unwrap();
    let nodes = path(&graph, set);
    let climbs: f64 = nodes.windows(2).map(|w| (points[w[1]][2] - points[w[0]][2]).max(0.0)).sum();
    assert_eq!(climbs, 0.0, "the vadose path climbs {climbs:.2} m");
    // No climb would also hold in a homogeneous medium here; what makes the path vadose is
    // that going down is cheap and going up dear: the same route climbed costs far more.
    let route_cost = |graph: &CostGraph, nodes: &[usize]| -> f64 {
        let edge = |u: usize, v: usize| graph.out_edges_in(set, u).find(|e| e.0 == v).unwrap().1;
        nodes.windows(2).map(|w| f64::from(edge(w[0], w[1]))).sum()
    };
    let down = route_cost(&graph, &nodes);
    let swapped: Vec<[f64; 3]> =
        [points[1], points[0]].into_iter().chain(points[2..].iter().copied()).collect();
    let graph_up = costed(&scene, &swapped);
    let up = route_cost(&graph_up, &path(&graph_up, set));
    eprintln!("vadose route: {down:.1} down, {up:.1} up");
    assert!(up > 3.0 * down, "climbing ({up:.1}) should cost far more than falling ({down:.1})");
}

#[test]
fn costs_do_not_depend_on_the_thread_count() {
    let size = [100.0, 100.0, 50.0];
    let extra = r#"
[[geology.horizons]]
name = "bed"
elevation = 25.0
dip = 3.0
[[geology.fractures]]
name = "n045"
azimuth = 45.0
[costgraph]
k = 30
symmetrise = true
"#;
    let scene = scene(size, extra);
    let points = cloud(12_000, size, [[1.0, 1.0, 1.0], [99.0, 99.0, 49.0]], 5);
    let with = |threads: usize| {
        let pool = rayon::ThreadPoolBuilder::new().num_threads(threads).build().unwrap();
        pool.install(|| costed(&scene, &points))
    };
    let (one, two) = (with(1), with(2));
    assert!(one == two, "the graphs differ between 1 and 2 threads");
    // Rows costed on demand, by two threads reading them at once, cost what rows costed all
    // at once do.
    let lazy = build_points(&CostgraphView::of(&scene), &points).unwrap();
    lazy.cost_from(&CostgraphView::of(&scene), &points, Costing::OnDemand).unwrap();
    let pool = rayon::ThreadPoolBuilder::new().num_threads(2).build().unwrap();
    pool.install(|| {
        let read = |u: usize| lazy.row_costs(0, u).len();
        rayon::join(
            || (0..points.len()).map(read).sum::<usize>(),
            || (0..points.len()).rev().map(read).sum::<usize>(),
        )
    });
    for u in 0..points.len() {
        assert_eq!(lazy.row_costs(0, u), one.row_costs(0, u), "row {u}");
        assert!(one.row_costs(0, u).iter().all(|&c| c > 0.0));
    }
    // Rows costed ahead (by a thread that never waits) cost the same; a row is costed once.
    let ahead = build_points(&CostgraphView::of(&scene), &points).unwrap();
    ahead.cost_from(&CostgraphView::of(&scene), &points, Costing::OnDemand).unwrap();
    let made = pool.install(|| {
        let read = |u: usize| usize::from(ahead.cost_row_ahead(u));
        rayon::join(
            || (0..points.len()).map(read).sum::<usize>(),
            || (0..points.len()).rev().map(read).sum::<usize>(),
        )
    });
    assert_eq!(made.0 + made.1, points.len(), "every row costed by exactly one of the two");
    for u in 0..points.len() {
        assert!(!ahead.cost_row_ahead(u), "row {u} costed twice");
        assert_eq!(ahead.row_costs(0, u), one.row_costs(0, u), "row {u}");
    }
}

/// Largest distance from the path's nodes to the segment between its ends.
fn largest_offset(points: &[[f64; 3]], nodes: &[usize]) -> f64 {
    let (a, b) = (at(points, nodes[0]), at(points, *nodes.last().unwrap()));
    nodes
        .iter()
        .map(|&n| {
            let p = at(points, n);
            let t = ((p - a).dot(b - a) / (b - a).length_squared()).clamp(0.0, 1.0);
            p.distance(a + (b - a) * t)
        })
        .fold(0.0, f64::max)
}

#[test]
fn a_forced_link_is_a_cheap_straight_corridor_under_paris2021() {
    let size = [200.0, 60.0, 100.0];
    let (a, b) = ([10.0, 30.0, 80.0], [190.0, 30.0, 80.0]);
    // A horizon 60 m below the two key points draws the least-cost path down to it and back.
    let text = |forced: &str| {
        format!(
            r#"
name = "t"
[domain]
min = [0, 0, 0]
max = [200, 60, 100]
[terrain]
kind = "plane"
elevation = 100
[[geology.horizons]]
name = "bed"
elevation = 20
[[geology.water_tables]]
name = "wt"
elevation = -1000
[[keypoints]]
name = "a"
kind = "sink"
position = {a:?}
[[keypoints]]
name = "b"
kind = "spring"
position = {b:?}
water_table = "wt"
[costgraph]
model = "paris2021"
k = 30
w_horizon = 4.0
w_fracture = 0.0
w_permeability = 0.0
horizon_distance = 10.0
forced_link_radius = 6.0
[skeleton]
mode = "gamma"
{forced}
"#
        )
    };
    let points = cloud(20_000, size, [a, b], 6);
    let route = |forced: &str| {
        let scene = Scene::parse(&text(forced), Path::new("t.toml")).unwrap();
        let graph = costed(&scene, &points);
        path(&graph, 0)
    };
    let free = route("");
    let lowest = free.iter().map(|&n| points[n][2]).fold(f64::INFINITY, f64::min);
    assert!(
        lowest < 35.0,
        "without the forced link the path should dive to the horizon (lowest {lowest:.1} m)"
    );
    let forced = route("forced_links = [[\"a\", \"b\"]]");
    let offset = largest_offset(&points, &forced);
    let ratio = length(&points, &forced) / at(&points, 0).distance(at(&points, 1));
    eprintln!("forced link: largest offset {offset:.2} m, path / straight line {ratio:.3}");
    assert!(offset <= 6.0, "the forced path leaves its corridor by {offset:.2} m");
    assert!(ratio < 1.1, "the forced path is {ratio:.3} × the straight line");
    // Under karstnsim2024 forced links do not change the costs (KarstNSim has none); the
    // graphs differ only in the scene sections they were made under.
    let k = |forced: &str| {
        let t = text(forced).replace("model = \"paris2021\"", "model = \"karstnsim2024\"");
        every_cost(&costed(&Scene::parse(&t, Path::new("t.toml")).unwrap(), &points))
    };
    assert!(k("") == k("forced_links = [[\"a\", \"b\"]]"));
}

/// A scene over a 100 m cube with three water tables, each named by a spring in `named`.
fn three_water_tables(named: &[&str]) -> Scene {
    let tables: String = [("wt-a", 30.0), ("wt-b", 45.0), ("wt-c", 70.0)]
        .iter()
        .map(|(name, z)| format!("[[geology.water_tables]]\nname = \"{name}\"\nelevation = {z}\ndip = 5.0\n"))
        .collect();
    let springs: String = named
        .iter()
        .enumerate()
        .map(|(i, name)| {
            format!(
                "[[keypoints]]\nname = \"s{i}\"\nkind = \"spring\"\nposition = [{}, 2, 1]\nwater_table = \"{name}\"\n",
                2 + i
            )
        })
        .collect();
    let text = format!(
        "name = \"t\"\n[domain]\nmin = [0, 0, 0]\nmax = [100, 100, 100]\n[terrain]\nkind = \"plane\"\nelevation = 100\n{tables}[[keypoints]]\nname = \"a\"\nkind = \"sink\"\nposition = [1, 1, 1]\n{springs}[costgraph]\nk = 20\n"
    );
    Scene::parse(&text, Path::new("t.toml")).unwrap()
}

#[test]
fn every_cost_set_costs_what_a_graph_of_its_water_table_alone_does() {
    let points = cloud(8_000, [100.0; 3], [[1.0, 1.0, 1.0], [99.0, 99.0, 99.0]], 6);
    let all = costed(&three_water_tables(&["wt-a", "wt-b", "wt-c"]), &points);
    assert_eq!(all.cost_sets.len(), 3);
    // Rows stored apart near the water tables, shared above and deep below them.
    let share = all.own_row_share();
    assert!(share > 0.2 && share < 0.8, "own rows {share}");
    for (set, name) in ["wt-a", "wt-b", "wt-c"].into_iter().enumerate() {
        let alone = costed(&three_water_tables(&[name]), &points);
        assert_eq!(alone.cost_sets.len(), 1);
        assert!(alone.own_rows.is_empty());
        for node in 0..all.node_count() {
            assert_eq!(all.row_costs(set, node), alone.row_costs(0, node), "set {name}, row {node}");
        }
        assert_eq!(all.cost_sets[set].min_cost_per_metre, alone.cost_sets[0].min_cost_per_metre);
    }
}
