//! Times one cost-graph build on uniform random points in a scene's domain (in Morton order), as `cargo xtask
//! bench --costgraph` does, and prints a fingerprint of the result (to check that an
//! optimisation leaves the graph bit-identical). Small enough to run under callgrind:
//!
//! `cargo run --release -p karst-costgraph --example costbench -- SCENE SAMPLES K [RUNS]`

use karst_costgraph::CostgraphView;
use karst_scene::SceneView;
use std::hash::{DefaultHasher, Hash, Hasher};
use std::path::Path;
use std::time::Instant;

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let scene_path = args.get(1).map(String::as_str).unwrap_or("fixtures/scenes/default.toml");
    let samples: usize = args.get(2).and_then(|s| s.parse().ok()).unwrap_or(100_000);
    let k: usize = args.get(3).and_then(|s| s.parse().ok()).unwrap_or(50);
    let runs: usize = args.get(4).and_then(|s| s.parse().ok()).unwrap_or(1);
    let mut scene = karst_scene::Scene::load(Path::new(scene_path)).expect("scene");
    scene.costgraph_mut().k = k;
    let mut rng = karst_scene::rng::Random::stream(scene.seed(), "bench", "costgraph-points");
    let (min, max) = (scene.domain().min, scene.domain().max);
    let points: Vec<[f64; 3]> =
        (0..samples).map(|_| std::array::from_fn(|axis| rng.range(min[axis], max[axis]))).collect();
    // In the sampler's storage order, as the bench does.
    let order = karst_sampling::morton_permutation(&points, 0, (min, max));
    let points: Vec<[f64; 3]> = order.iter().map(|&i| points[i as usize]).collect();
    let mut times = Vec::new();
    let mut graph = None;
    for _ in 0..runs.max(1) {
        drop(graph.take());
        let start = Instant::now();
        graph = Some(karst_costgraph::build_points(&CostgraphView::of(&scene), &points).expect("graph"));
        times.push(start.elapsed().as_secs_f64());
    }
    let graph = graph.expect("one run");
    let mut h = DefaultHasher::new();
    graph.offsets.hash(&mut h);
    graph.targets.hash(&mut h);
    graph.own_rows.hash(&mut h);
    // The costs are made for the rows the searches read; here every row, after the timing.
    graph
        .cost_from(&CostgraphView::of(&scene), &points, karst_costgraph::Costing::Every)
        .expect("the graph's own scene");
    for set in 0..graph.cost_sets.len() {
        for node in 0..graph.node_count() {
            graph.row_costs(set, node).iter().map(|c| c.to_bits()).for_each(|bits| bits.hash(&mut h));
        }
    }
    let topology = h.finish();
    format!("{:?}", graph.summary).hash(&mut h);
    times.sort_by(f64::total_cmp);
    println!(
        "{samples} samples k={k}: median {:.4} s of {:?}; edges {}; graph {topology:016x}; with summary {:016x}",
        times[times.len() / 2],
        times,
        graph.edge_count(),
        h.finish()
    );
}
