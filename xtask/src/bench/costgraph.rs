//! The cost graph's budget cases: random points in a scene's domain, only the graph timed.

use std::path::Path;
use std::time::Instant;

use karst_costgraph::CostgraphView;
use karst_scene::SceneView;
use karst_stage::StageError;

use super::median;
use super::probes::{cpu_seconds, peak_memory, reset_peak_memory};

/// One cost-graph budget case: `samples` uniform random points (seeded) in the scene's domain,
/// in Morton order, `k` neighbours, the scene's geology and cost model. Only the graph build is timed.
pub struct CostgraphCase {
    pub samples: usize,
    pub k: usize,
}

/// What a cost-graph case measured: median seconds, edges, bytes per edge of the graph and the
/// process's peak resident memory during the builds (Linux; None elsewhere).
pub struct CostgraphTimes {
    pub seconds: f64,
    /// Median CPU seconds of the process (all threads) per build: on a shared machine, wall
    /// time over-states what the build needs.
    pub cpu_seconds: Option<f64>,
    pub edges: usize,
    pub bytes_per_edge: f64,
    pub peak_bytes: Option<u64>,
}

/// Times `case` under `scene` (median of `runs` builds).
pub fn time_costgraph(scene: &Path, case: &CostgraphCase, runs: usize) -> Result<CostgraphTimes, StageError> {
    let mut scene = karst_scene::Scene::load(scene)?;
    scene.costgraph_mut().k = case.k;
    let mut rng = karst_scene::rng::Random::stream(scene.seed(), "bench", "costgraph-points");
    let (min, max) = (scene.domain().min, scene.domain().max);
    let points: Vec<[f64; 3]> =
        (0..case.samples).map(|_| std::array::from_fn(|axis| rng.range(min[axis], max[axis]))).collect();
    // Stored as the sampler stores samples, along a Morton curve: the order the cost graph
    // works in (chunks of consecutive nodes).
    let order = karst_sampling::morton_permutation(&points, 0, (min, max));
    let points: Vec<[f64; 3]> = order.iter().map(|&i| points[i as usize]).collect();
    reset_peak_memory();
    let mut times = Vec::new();
    let mut cpu = Vec::new();
    let mut last = None;
    for _ in 0..runs.max(1) {
        drop(last.take());
        let (start, cpu_start) = (Instant::now(), cpu_seconds());
        let graph =
            karst_costgraph::build_points(&CostgraphView::of(&scene), &points).map_err(StageError::input)?;
        times.push(start.elapsed().as_secs_f64());
        cpu.extend(cpu_seconds().zip(cpu_start).map(|(end, start)| end - start));
        last = Some(graph);
    }
    let graph = last.expect("at least one run");
    Ok(CostgraphTimes {
        seconds: median(times),
        cpu_seconds: (!cpu.is_empty()).then(|| median(cpu)),
        edges: graph.edge_count(),
        bytes_per_edge: graph.bytes_in_memory() as f64 / graph.edge_count().max(1) as f64,
        peak_bytes: peak_memory(),
    })
}
