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
