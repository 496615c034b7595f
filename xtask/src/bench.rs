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

fn median(mut values: Vec<f64>) -> f64 {
    values.sort_by(f64::total_cmp);
    values[values.len() / 2]
}

fn scratch_dir(scene: &Path) -> PathBuf {
    let name = scene.file_stem().map(|s| s.to_string_lossy().into_owned()).unwrap_or_default();
    std::env::temp_dir().join(format!("karstgen-bench-{}-{name}", std::process::id()))
}

/// The skeleton budgets of issue 5, timed apart from sampling and the cost graph: (case, samples,
/// median seconds). The γ-skeleton of the looping preset resampled to about 60k samples, and a
/// KarstNSim network of the karstnsim preset's 5 sinks and spring S1 on about 100k samples with
/// k = 50.
pub fn time_skeleton_budgets(runs: usize) -> Result<Vec<(String, usize, f64)>, StageError> {
    use karst_geology::{KeyPointKind, Scene};
    use karst_skeleton::search::EdgeCosts;
    use karst_skeleton::{assemble::NetworkBuilder, gamma, karstnsim, routing};

    let prepare = |path: &str, edit: &dyn Fn(&mut Scene)| -> Result<_, StageError> {
        let mut scene = Scene::load(Path::new(path))?;
        edit(&mut scene);
        let samples = karst_sampling::stage::sample_scene(&scene)?;
        let graph = karst_costgraph::stage::build(&scene, &samples)?;
        Ok((scene, samples, graph))
    };
    let mut results = Vec::new();
    let (scene, samples, graph) = prepare("fixtures/scenes/looping.toml", &|s| s.sampling.radius = 8.8)?;
    let mut times = Vec::new();
    for _ in 0..runs.max(1) {
        let start = Instant::now();
        gamma::network(&scene, &samples, &graph, &mut NetworkBuilder::default())?;
        times.push(start.elapsed().as_secs_f64());
    }
    results.push(("γ-skeleton, looping preset (47 key points)".to_string(), samples.len(), median(times)));
    let one_spring = |s: &mut Scene| {
        s.keypoints.retain(|k| k.name != "S2");
        s.connectivity.matrix = None;
        s.sampling.radius = 14.1;
        s.costgraph.k = 50;
    };
    let (scene, samples, graph) = prepare("fixtures/scenes/karstnsim.toml", &one_spring)?;
    debug_assert_eq!(scene.keypoints_of(KeyPointKind::Spring).count(), 1);
    let cost_set = |_: &str| -> &dyn EdgeCosts { &graph };
    let phase = karstnsim::PhaseSetup::single(&scene, &graph);
    let mut times = Vec::new();
    for _ in 0..runs.max(1) {
        let start = Instant::now();
        karstnsim::route(&scene, &samples, &graph, &cost_set, &routing::sinks_in_order(&scene), &phase)?;
        times.push(start.elapsed().as_secs_f64());
    }
    results.push(("KarstNSim, 5 sinks, 1 spring, k = 50".to_string(), samples.len(), median(times)));
    Ok(results)
}
