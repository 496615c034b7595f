//! The sdf budgets: building the tree and evaluating the field, on a synthetic network and on a
//! preset's.

use std::path::Path;
use std::time::Instant;

use glam::DVec3;
use karst_artifact::{Provenance, StageId, read_artifact};
use karst_pipeline::registry;
use karst_pipeline::scene::SceneFile;
use karst_scene::SceneView;
use karst_sdf::{CarvedTerrain, SdfView};
use karst_stage::{Job, StageError};

use super::probes::cpu_seconds;
use super::{median, scratch_dir};

/// The sdf stage's budgets (issue 7) on one tree: build time, mean evaluation time and memory
/// per primitive.
pub struct SdfBench {
    pub primitives: usize,
    pub by_kind: Vec<(&'static str, usize)>,
    pub build_seconds: f64,
    pub eval_uniform_ns: f64,
    pub eval_near_ns: f64,
    /// The same in CPU time of the process (Linux): on a shared machine wall time also counts
    /// the waits for a core.
    pub eval_uniform_cpu_ns: Option<f64>,
    pub eval_near_cpu_ns: Option<f64>,
    /// [karst, water] in-memory bytes.
    pub memory_bytes: [usize; 2],
    pub artifact_bytes: u64,
}

/// Times `karst_sdf::build` and `CarvedTerrain::eval` on `conduits` synthetic conduits of 12
/// nodes: evaluations at 200k points uniform in the domain and 200k within 6 m of a node.
pub fn sdf_network(conduits: usize, runs: usize) -> Result<SdfBench, StageError> {
    let scene = karst_scene::Scene::parse(karst_sdf::synthetic::SCENE, Path::new("synthetic.toml"))?;
    let (skeleton, hydro) = karst_sdf::synthetic::network(5, conduits, 12);
    sdf_tree(&scene, &skeleton, &hydro, runs)
}

/// The same on the tree of a preset scene: its stages up to hydro run once (not timed).
pub fn sdf_preset(scene: &Path, runs: usize) -> Result<SdfBench, StageError> {
    let out = scratch_dir(scene);
    let loaded = SceneFile::load(scene)?;
    let job = Job::new(scene, &loaded.scene, &out);
    for stage in [StageId::Sampling, StageId::Costgraph, StageId::Skeleton, StageId::Hydro] {
        registry::stage(stage).run(&job)?;
    }
    let (_, skeleton) = read_artifact::<karst_skeleton::Skeleton>(&job.artifact(StageId::Skeleton))?;
    let (_, hydro) = read_artifact::<karst_hydro::Hydro>(&job.artifact(StageId::Hydro))?;
    drop(out);
    sdf_tree(&loaded.scene, &skeleton, &hydro, runs)
}

fn sdf_tree(
    scene: &karst_scene::Scene,
    skeleton: &karst_skeleton::Skeleton,
    hydro: &karst_hydro::Hydro,
    runs: usize,
) -> Result<SdfBench, StageError> {
    let mut builds = Vec::new();
    let mut model = None;
    for _ in 0..runs.max(1) {
        let start = Instant::now();
        let built = karst_sdf::build(&SdfView::of(scene), skeleton, hydro).map_err(StageError::input)?;
        let field = CarvedTerrain::new(built);
        builds.push(start.elapsed().as_secs_f64());
        model = Some(field);
    }
    let field = model.expect("at least one run");
    let dir = scratch_dir(Path::new(&format!("sdf-{}", scene.name())));
    std::fs::create_dir_all(&dir).map_err(|e| StageError::failure(format!("{}: {e}", dir.display())))?;
    let provenance = Provenance {
        producer: "bench".into(),
        inputs: vec![],
        params: "bench".into(),
        frame: Default::default(),
    };
    let header = karst_artifact::write_artifact(&dir.join("sdf.bin"), &provenance, field.model())?;
    drop(dir);

    let [uniform, near] = karst_sdf::synthetic::eval_points(&field, skeleton, 200_000);
    let time = |points: &[DVec3]| {
        let (mut wall, mut cpu) = (Vec::new(), Vec::new());
        for _ in 0..runs.max(1) {
            let (start, cpu_start) = (Instant::now(), cpu_seconds());
            let sum: f64 = points.iter().map(|&p| field.eval(p)).sum();
            std::hint::black_box(sum);
            wall.push(start.elapsed().as_secs_f64() * 1e9 / points.len() as f64);
            cpu.extend(cpu_seconds().zip(cpu_start).map(|(e, s)| (e - s) * 1e9 / points.len() as f64));
        }
        (median(wall), (!cpu.is_empty()).then(|| median(cpu)))
    };
    let by_kind: Vec<(&'static str, usize)> = field.model().primitive_counts().into_iter().collect();
    let primitives = by_kind.iter().filter(|(k, _)| *k != "water").map(|(_, n)| n).sum();
    let (eval_uniform_ns, eval_uniform_cpu_ns) = time(&uniform);
    let (eval_near_ns, eval_near_cpu_ns) = time(&near);
    Ok(SdfBench {
        primitives,
        by_kind,
        build_seconds: median(builds),
        eval_uniform_ns,
        eval_near_ns,
        eval_uniform_cpu_ns,
        eval_near_cpu_ns,
        memory_bytes: field.memory(),
        artifact_bytes: header.payload_len,
    })
}
