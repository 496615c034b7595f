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

/// The sdf stage's budgets on a synthetic network (issue 7; the looping preset is not merged
/// yet): build time, mean evaluation time and memory per primitive.
pub struct SdfBench {
    pub primitives: usize,
    pub by_kind: Vec<(&'static str, usize)>,
    pub build_seconds: f64,
    pub eval_uniform_ns: f64,
    pub eval_near_ns: f64,
    /// [karst, water] in-memory bytes.
    pub memory_bytes: [usize; 2],
    pub artifact_bytes: u64,
}

/// Times `karst_sdf::build` and `CarvedTerrain::eval` on `conduits` synthetic conduits of 12
/// nodes: evaluations at 200k points uniform in the domain and 200k within 6 m of a leaf.
pub fn sdf_network(conduits: usize, runs: usize) -> Result<SdfBench, StageError> {
    use glam::DVec3;
    use karst_sdf::{CarvedTerrain, build, synthetic};

    let scene = synthetic::scene();
    let (skeleton, hydro) = synthetic::network(5, conduits, 12);
    let mut builds = Vec::new();
    let mut model = None;
    for _ in 0..runs.max(1) {
        let start = Instant::now();
        let built = build::build(&scene, &skeleton, &hydro)?;
        let field = CarvedTerrain::new(built);
        builds.push(start.elapsed().as_secs_f64());
        model = Some(field);
    }
    let field = model.expect("at least one run");
    let dir = scratch_dir(Path::new("sdf-synthetic"));
    std::fs::create_dir_all(&dir).map_err(|e| StageError::failure(format!("{}: {e}", dir.display())))?;
    let run = karst_artifact::cli::StageRun::new(Stage::Sdf, &dir);
    let header =
        karst_artifact::write_artifact(&dir.join("sdf.bin"), &run.provenance("bench"), field.model())?;
    let _ = std::fs::remove_dir_all(&dir);

    let mut state = 12345u64;
    let mut unit = move || {
        state = state.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
        (state >> 11) as f64 / (1u64 << 53) as f64
    };
    let d = &field.model().domain;
    let (lo, hi) = (DVec3::from_array(d.min), DVec3::from_array(d.max));
    let uniform: Vec<DVec3> =
        (0..200_000).map(|_| lo + (hi - lo) * DVec3::new(unit(), unit(), unit())).collect();
    let anchors: Vec<DVec3> = skeleton.nodes.iter().map(|n| DVec3::from_array(n.position)).collect();
    let near: Vec<DVec3> = (0..200_000)
        .map(|_| {
            let a = anchors[(unit() * anchors.len() as f64) as usize % anchors.len()];
            a + (DVec3::new(unit(), unit(), unit()) - 0.5) * 12.0
        })
        .collect();
    let time = |points: &[DVec3]| {
        let per_run: Vec<f64> = (0..runs.max(1))
            .map(|_| {
                let start = Instant::now();
                let sum: f64 = points.iter().map(|&p| field.eval(p)).sum();
                std::hint::black_box(sum);
                start.elapsed().as_secs_f64() * 1e9 / points.len() as f64
            })
            .collect();
        median(per_run)
    };
    let by_kind: Vec<(&'static str, usize)> = field.model().primitive_counts().into_iter().collect();
    let primitives = by_kind.iter().filter(|(k, _)| *k != "water").map(|(_, n)| n).sum();
    Ok(SdfBench {
        primitives,
        by_kind,
        build_seconds: median(builds),
        eval_uniform_ns: time(&uniform),
        eval_near_ns: time(&near),
        memory_bytes: field.memory(),
        artifact_bytes: header.payload_len,
    })
}
