//! The streams budgets (issue 22): the surface network and its classification (≤ 50 ms on the
//! default scene), what the streams add to the default scene's pipeline (≤ 10 %), and the
//! field evaluations per vertex of the carved waterfall terrain against the same terrain
//! uncarved.
//!
//! The pipeline's extra cost is measured in pairs, in process: on the same upstream artifacts,
//! each run builds the sdf model and meshes it (the sdf and mesher stages' `build`) with the
//! surface water and without it, in alternating order, and the streams stage's `build` once;
//! the overhead is the median of the paired differences plus the streams' own median, beside
//! the whole pipeline's time.

use std::path::Path;
use std::time::Instant;

use karst_artifact::{StageId, read_artifact};
use karst_hydro::Hydro;
use karst_mesher::{MesherStage, MesherView, anchors, mesh_with};
use karst_pipeline::registry;
use karst_pipeline::scene::SceneFile;
use karst_scene::{Scene, SceneView};
use karst_sdf::{CarvedTerrain, SdfModel, SdfStage, SdfView};
use karst_skeleton::Skeleton;
use karst_stage::{Job, Stage, StageError};
use karst_streams::{Streams, StreamsStage, StreamsView};

use super::probes::cpu_seconds;
use super::{median, scratch_dir};

/// The surface network of one scene, timed.
pub struct NetworkTime {
    /// Median seconds of the streams stage's build (trajectories, flows, classification).
    pub seconds: f64,
    /// Mean CPU seconds of the process per build over all runs (the clock ticks in 10 ms), when
    /// readable.
    pub cpu_seconds: Option<f64>,
    pub headline: String,
}

/// What the streams add to a scene's pipeline.
pub struct Overhead {
    /// The whole pipeline, every stage run in process with its files (median of `runs`).
    pub pipeline_seconds: f64,
    pub streams_seconds: f64,
    /// Median of the paired differences with − without the surface water.
    pub sdf_extra: f64,
    pub mesher_extra: f64,
    /// The mesher's build without the surface water (median), for scale.
    pub mesher_without: f64,
    /// Median of the paired differences of sdf + mesher in CPU seconds of the process (all
    /// threads; less sensitive than wall time to waiting for a core), when readable.
    pub cpu_extra: Option<f64>,
    /// sdf + mesher without the surface water, CPU seconds (median).
    pub cpu_without: Option<f64>,
}

/// The terrain meshed with its streams carved and without them.
pub struct Carving {
    pub triangles: [usize; 2],
    /// Field evaluations per vertex of the carved terrain, [with, without] the streams.
    pub evaluations_per_vertex: [f64; 2],
}

/// The upstream artifacts of a scene, run once into a scratch folder (not timed).
struct Upstream {
    scene: Scene,
    skeleton: Skeleton,
    hydro: Hydro,
    streams: Streams,
}

fn upstream(scene: &Path) -> Result<Upstream, StageError> {
    let out = scratch_dir(scene);
    let loaded = SceneFile::load(scene)?;
    let job = Job::new(scene, &loaded.scene, &out);
    for stage in [StageId::Sampling, StageId::Costgraph, StageId::Skeleton, StageId::Hydro, StageId::Streams]
    {
        registry::stage(stage).run(&job)?;
    }
    let (_, skeleton) = read_artifact::<Skeleton>(&job.artifact(StageId::Skeleton))?;
    let (_, hydro) = read_artifact::<Hydro>(&job.artifact(StageId::Hydro))?;
    let (_, streams) = read_artifact::<Streams>(&job.artifact(StageId::Streams))?;
    Ok(Upstream { scene: loaded.scene, skeleton, hydro, streams })
}

/// Median wall and CPU seconds of the streams stage's build on `scene`.
pub fn time_network(scene: &Path, runs: usize) -> Result<NetworkTime, StageError> {
    let up = upstream(scene)?;
    let inputs = (up.hydro,);
    let mut wall = Vec::new();
    let mut headline = String::new();
    let cpu_start = cpu_seconds();
    for _ in 0..runs.max(1) {
        let start = Instant::now();
        let streams = StreamsStage::build(&StreamsView::of(&up.scene), &inputs).map_err(StageError::input)?;
        wall.push(start.elapsed().as_secs_f64());
        headline = StreamsStage::headline(&StreamsView::of(&up.scene), &streams);
    }
    let cpu = cpu_seconds().zip(cpu_start).map(|(e, s)| (e - s) / runs.max(1) as f64);
    Ok(NetworkTime { seconds: median(wall), cpu_seconds: cpu, headline })
}

/// The streams' share of `scene`'s pipeline, in pairs (see the module documentation).
pub fn overhead(scene: &Path, runs: usize) -> Result<Overhead, StageError> {
    let pipeline_seconds = super::pipeline::time_scene(scene, runs)?.iter().map(|(_, s)| s).sum();
    let up = upstream(scene)?;
    let with_inputs = (up.skeleton.clone(), up.hydro.clone(), up.streams.clone());
    let (mut streams, mut sdf, mut mesher, mut bare_mesher) =
        (Vec::new(), Vec::new(), Vec::new(), Vec::new());
    let (mut cpu_extra, mut cpu_without) = (Vec::new(), Vec::new());
    for run in 0..runs.max(1) {
        let start = Instant::now();
        StreamsStage::build(&StreamsView::of(&up.scene), &(up.hydro.clone(),)).map_err(StageError::input)?;
        streams.push(start.elapsed().as_secs_f64());
        let mut pair = [0.0; 4];
        let mut cpu_pair = [None; 2];
        // Alternate which goes first, so that warm caches and a busy neighbour favour neither.
        for with in if run % 2 == 0 { [true, false] } else { [false, true] } {
            let (start, cpu_start) = (Instant::now(), cpu_seconds());
            let model = if with {
                SdfStage::build(&SdfView::of(&up.scene), &with_inputs)
            } else {
                karst_sdf::build(&SdfView::of(&up.scene), &up.skeleton, &up.hydro)
            }
            .map_err(StageError::input)?;
            let built = start.elapsed().as_secs_f64();
            let start = Instant::now();
            MesherStage::build(&MesherView::of(&up.scene), &(model,)).map_err(StageError::input)?;
            let meshed = start.elapsed().as_secs_f64();
            let at = if with { 0 } else { 2 };
            pair[at] = built;
            pair[at + 1] = meshed;
            cpu_pair[usize::from(!with)] = cpu_seconds().zip(cpu_start).map(|(e, s)| e - s);
        }
        sdf.push(pair[0] - pair[2]);
        mesher.push(pair[1] - pair[3]);
        bare_mesher.push(pair[3]);
        if let [Some(with), Some(without)] = cpu_pair {
            cpu_extra.push(with - without);
            cpu_without.push(without);
        }
    }
    let cpu = |v: Vec<f64>| (!v.is_empty()).then(|| median(v));
    Ok(Overhead {
        pipeline_seconds,
        streams_seconds: median(streams),
        sdf_extra: median(sdf),
        mesher_extra: median(mesher),
        mesher_without: median(bare_mesher),
        cpu_extra: cpu(cpu_extra),
        cpu_without: cpu(cpu_without),
    })
}

/// The terrain of `scene` meshed at `cell` (cave and water at half of it) with its streams
/// carved and without them: the carving's cost in field evaluations per vertex.
pub fn carving(scene: &Path, cell: f64) -> Result<Carving, StageError> {
    let up = upstream(scene)?;
    let bare =
        karst_sdf::build(&SdfView::of(&up.scene), &up.skeleton, &up.hydro).map_err(StageError::input)?;
    let carved = SdfStage::build(
        &SdfView::of(&up.scene),
        &(up.skeleton.clone(), up.hydro.clone(), up.streams.clone()),
    )
    .map_err(StageError::input)?;
    let anchors = anchors(up.scene.keypoints());
    let terrain = |model: SdfModel| mesh_with(&CarvedTerrain::new(model), cell, 0.5 * cell, &anchors).terrain;
    let (with, without) = (terrain(carved), terrain(bare));
    Ok(Carving {
        triangles: [with.triangles.len(), without.triangles.len()],
        evaluations_per_vertex: [with.evaluations_per_vertex(), without.evaluations_per_vertex()],
    })
}
