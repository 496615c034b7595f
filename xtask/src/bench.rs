//! `cargo xtask bench`: times every stage of the benchmark scenes, in process, and prints the
//! median of several runs per stage.

use std::path::{Path, PathBuf};
use std::time::Instant;

use karst_artifact::{Stage, StageError};

use crate::executor::{Executor, InProcess};

/// Median seconds per stage over `runs` full pipeline runs of `scene`.
pub fn time_scene(scene: &Path, runs: usize) -> Result<Vec<(Stage, f64)>, StageError> {
    let out = scratch_dir(scene);
    let mut times: Vec<Vec<f64>> = vec![Vec::new(); Stage::ALL.len()];
    for _ in 0..runs.max(1) {
        for (i, stage) in Stage::ALL.into_iter().enumerate() {
            let start = Instant::now();
            InProcess.run(stage, scene, &out)?;
            times[i].push(start.elapsed().as_secs_f64());
        }
    }
    let _ = std::fs::remove_dir_all(&out);
    Ok(Stage::ALL.into_iter().zip(times.into_iter().map(median)).collect())
}

/// Median seconds of `stage` alone on `scene` over `runs` runs (the earlier stages run once
/// first), and the headline of its last run.
pub fn time_stage(scene: &Path, stage: Stage, runs: usize) -> Result<(f64, String), StageError> {
    let out = scratch_dir(scene);
    for earlier in Stage::ALL.into_iter().take_while(|s| *s != stage) {
        InProcess.run(earlier, scene, &out)?;
    }
    let mut times = Vec::new();
    let mut headline = String::new();
    for _ in 0..runs.max(1) {
        let start = Instant::now();
        headline = InProcess.run(stage, scene, &out)?;
        times.push(start.elapsed().as_secs_f64());
    }
    let _ = std::fs::remove_dir_all(&out);
    Ok((median(times), headline))
}

fn median(mut values: Vec<f64>) -> f64 {
    values.sort_by(f64::total_cmp);
    values[values.len() / 2]
}

fn scratch_dir(scene: &Path) -> PathBuf {
    let name = scene.file_stem().map(|s| s.to_string_lossy().into_owned()).unwrap_or_default();
    std::env::temp_dir().join(format!("karstgen-bench-{}-{name}", std::process::id()))
}

/// One cost-graph budget case: `samples` uniform random points (seeded) in the scene's domain,
/// `k` neighbours, the scene's geology and cost model. Only the graph build is timed.
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
    let mut scene = karst_geology::Scene::load(scene)?;
    scene.costgraph.k = case.k;
    let mut rng = karst_geology::rng::Random::stream(scene.seed, "bench", "costgraph-points");
    let (min, max) = (scene.domain.min, scene.domain.max);
    let points: Vec<[f64; 3]> =
        (0..case.samples).map(|_| std::array::from_fn(|axis| rng.range(min[axis], max[axis]))).collect();
    reset_peak_memory();
    let mut times = Vec::new();
    let mut cpu = Vec::new();
    let mut last = None;
    for _ in 0..runs.max(1) {
        drop(last.take());
        let (start, cpu_start) = (Instant::now(), cpu_seconds());
        let graph = karst_costgraph::build_points(&scene, &points)?;
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

/// Resets the kernel's peak-RSS counter of this process (Linux ≥ 4.0).
fn reset_peak_memory() {
    let _ = std::fs::write("/proc/self/clear_refs", "5");
}

/// Peak resident memory of this process since the last reset, bytes.
fn peak_memory() -> Option<u64> {
    let status = std::fs::read_to_string("/proc/self/status").ok()?;
    let line = status.lines().find(|l| l.starts_with("VmHWM:"))?;
    let kb: u64 = line.split_whitespace().nth(1)?.parse().ok()?;
    Some(kb * 1024)
}

/// User + system CPU seconds of this process so far (Linux; clock ticks of 1/100 s).
fn cpu_seconds() -> Option<f64> {
    let stat = std::fs::read_to_string("/proc/self/stat").ok()?;
    let fields: Vec<&str> = stat.rsplit_once(')')?.1.split_whitespace().collect();
    let ticks = |i: usize| fields.get(i)?.parse::<f64>().ok();
    Some((ticks(11)? + ticks(12)?) / 100.0)
}
