//! Every stage of a scene timed in process, and one stage alone.

use std::path::Path;
use std::time::Instant;

use karst_artifact::StageId;
use karst_pipeline::registry;
use karst_pipeline::scene::SceneFile;
use karst_stage::{Job, StageError};

use super::{median, scratch_dir};

/// Median seconds per stage over `runs` full pipeline runs of `scene`.
pub fn time_scene(scene: &Path, runs: usize) -> Result<Vec<(StageId, f64)>, StageError> {
    let out = scratch_dir(scene);
    let loaded = SceneFile::load(scene)?;
    let job = Job::new(scene, &loaded.scene, &out);
    let mut times: Vec<Vec<f64>> = vec![Vec::new(); StageId::ALL.len()];
    for _ in 0..runs.max(1) {
        for (i, stage) in StageId::ALL.into_iter().enumerate() {
            let start = Instant::now();
            registry::stage(stage).run(&job)?;
            times[i].push(start.elapsed().as_secs_f64());
        }
    }
    Ok(StageId::ALL.into_iter().zip(times.into_iter().map(median)).collect())
}

/// Median seconds of `stage` alone on `scene` over `runs` runs (the earlier stages run once
/// first), and the headline of its last run.
pub fn time_stage(scene: &Path, stage: StageId, runs: usize) -> Result<(f64, String), StageError> {
    let out = scratch_dir(scene);
    let loaded = SceneFile::load(scene)?;
    let job = Job::new(scene, &loaded.scene, &out);
    for earlier in StageId::ALL.into_iter().take_while(|s| *s != stage) {
        registry::stage(earlier).run(&job)?;
    }
    let mut times = Vec::new();
    let mut headline = String::new();
    for _ in 0..runs.max(1) {
        let start = Instant::now();
        headline = registry::stage(stage).run(&job)?.headline;
        times.push(start.elapsed().as_secs_f64());
    }
    Ok((median(times), headline))
}
