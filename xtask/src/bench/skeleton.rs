//! The skeleton budgets: the mode's paths alone, sampling and the cost graph excluded.

use std::path::Path;
use std::time::Instant;

use karst_costgraph::CostgraphView;
use karst_sampling::SamplingView;
use karst_scene::{KeyPointKind, Scene, SceneView, keypoints_of};
use karst_skeleton::SkeletonView;
use karst_stage::StageError;

use super::median;

/// Sampling radius of the KarstNSim skeleton budget case (the preset's 28 m × 0.39, about 100k
/// samples).
const KARSTNSIM_BENCH_RADIUS: f64 = 11.0;

/// The skeleton budgets of issue 5, timed apart from sampling and the cost graph: (case, samples,
/// median seconds). The γ-skeleton of the looping preset resampled to about 60k samples, and a
/// KarstNSim network of the karstnsim preset's 5 sinks and spring S1 on about 100k samples with
/// k = 50.
pub fn time_skeleton_budgets(runs: usize) -> Result<Vec<(String, usize, f64)>, StageError> {
    let prepare = |path: &str, edit: &dyn Fn(&mut Scene)| -> Result<_, StageError> {
        let mut scene = Scene::load(Path::new(path))?;
        edit(&mut scene);
        let samples = karst_sampling::build(&SamplingView::of(&scene)).map_err(StageError::input)?;
        let graph =
            karst_costgraph::build(&CostgraphView::of(&scene), &samples).map_err(StageError::input)?;
        Ok((scene, samples, graph))
    };
    let time_paths = |scene: &Scene, samples, graph| -> Result<f64, StageError> {
        let mut times = Vec::new();
        for _ in 0..runs.max(1) {
            let start = Instant::now();
            karst_skeleton::mode_paths(&SkeletonView::of(scene), samples, graph)
                .map_err(StageError::input)?;
            times.push(start.elapsed().as_secs_f64());
        }
        Ok(median(times))
    };
    let mut results = Vec::new();
    let (scene, samples, graph) =
        prepare("fixtures/scenes/looping.toml", &|s| s.sampling_mut().radius = Some(8.8))?;
    let seconds = time_paths(&scene, &samples, &graph)?;
    results.push(("γ-skeleton, looping preset (47 key points)".to_string(), samples.len(), seconds));
    let one_spring = |s: &mut Scene| {
        s.keypoints_mut().retain(|k| k.name != "S2");
        s.connectivity_mut().matrix = None;
        // About 100k samples: every radius (the layers' too) scaled by the same factor.
        let scale = KARSTNSIM_BENCH_RADIUS / s.sampling().radius.unwrap_or(KARSTNSIM_BENCH_RADIUS);
        s.sampling_mut().radius = Some(KARSTNSIM_BENCH_RADIUS);
        for radius in s.geology_mut().layers.iter_mut().filter_map(|l| l.radius.as_mut()) {
            *radius *= scale;
        }
        s.costgraph_mut().k = 50;
    };
    let (scene, samples, graph) = prepare("fixtures/scenes/karstnsim.toml", &one_spring)?;
    debug_assert_eq!(keypoints_of(scene.keypoints(), KeyPointKind::Spring).count(), 1);
    let seconds = time_paths(&scene, &samples, &graph)?;
    results.push(("KarstNSim, 5 sinks, 1 spring, k = 50".to_string(), samples.len(), seconds));
    Ok(results)
}
