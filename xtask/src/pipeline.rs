//! Running the pipeline like make: a stage runs when its artifact is missing or its key
//! differs from the key it would write now (stage, producer version, the scene sections it
//! reads, its inputs' payload hashes); otherwise it is up to date.

use std::path::{Path, PathBuf};
use std::time::Instant;

use karst_artifact::pipeline::{producer, stage_key};
use karst_artifact::{InputRef, Payload, Stage, StageError, read_header};
use karst_geology::Scene;

use crate::executor::Executor;

/// Which stages to run.
#[derive(Debug, Clone, Default)]
pub struct Selection {
    /// Run this stage and every later one, even when up to date.
    pub from: Option<Stage>,
    /// Run only this stage, even when up to date.
    pub only: Option<Stage>,
    /// Run every stage, even when up to date.
    pub force: bool,
}

/// What happened to one stage.
#[derive(Debug, Clone, PartialEq)]
pub enum Outcome {
    Ran { headline: String },
    UpToDate,
    Skipped,
}

/// One line of the run report.
#[derive(Debug, Clone)]
pub struct StageReport {
    pub stage: Stage,
    pub outcome: Outcome,
    pub seconds: f64,
}

/// Runs the pipeline on `scene_path` into `out`, printing a line per stage when `verbose`.
pub fn run(
    scene_path: &Path,
    out: &Path,
    selection: &Selection,
    executor: &dyn Executor,
    verbose: bool,
) -> Result<Vec<StageReport>, StageError> {
    let scene = Scene::load(scene_path)?;
    std::fs::create_dir_all(out).map_err(|e| {
        StageError::failure(format!("{}: cannot create the output folder: {e}", out.display()))
    })?;
    let mut reports = Vec::new();
    for stage in Stage::ALL {
        let start = Instant::now();
        let outcome = if !selected(stage, selection) {
            Outcome::Skipped
        } else if !forced(stage, selection) && up_to_date(&scene, stage, out) {
            Outcome::UpToDate
        } else {
            Outcome::Ran { headline: executor.run(stage, scene_path, out)? }
        };
        let report = StageReport { stage, outcome, seconds: start.elapsed().as_secs_f64() };
        if verbose {
            print_report(&report);
        }
        reports.push(report);
    }
    Ok(reports)
}

fn selected(stage: Stage, selection: &Selection) -> bool {
    selection.only.is_none_or(|only| only == stage)
}

fn forced(stage: Stage, selection: &Selection) -> bool {
    selection.force || selection.only == Some(stage) || selection.from.is_some_and(|from| stage >= from)
}

/// The key `stage` would write now, if its inputs exist.
pub fn expected_key(scene: &Scene, stage: Stage, out: &Path) -> Option<String> {
    let inputs = stage
        .inputs()
        .iter()
        .map(|input| {
            let header = read_header(&out.join(input.file_name())).ok()?;
            Some(InputRef { name: input.kind().name().into(), payload_blake3: header.payload_blake3 })
        })
        .collect::<Option<Vec<_>>>()?;
    Some(stage_key(stage, &producer(stage), schema(stage), &scene.params_hash(stage), &inputs))
}

/// The payload schema this build writes for `stage`.
pub fn schema(stage: Stage) -> u32 {
    match stage {
        Stage::Sampling => karst_sampling::Samples::SCHEMA,
        Stage::Costgraph => karst_costgraph::CostGraph::SCHEMA,
        Stage::Skeleton => karst_skeleton::Skeleton::SCHEMA,
        Stage::Hydro => karst_hydro::Hydro::SCHEMA,
        Stage::Sdf => karst_sdf::SdfModel::SCHEMA,
        Stage::Mesher => karst_mesher::Mesh::SCHEMA,
        Stage::Metrics => karst_metrics::stage::MetricsReport::SCHEMA,
    }
}

fn up_to_date(scene: &Scene, stage: Stage, out: &Path) -> bool {
    let existing = read_header(&out.join(stage.file_name())).ok();
    match (existing, expected_key(scene, stage, out)) {
        (Some(header), Some(key)) => header.key == key,
        _ => false,
    }
}

fn print_report(report: &StageReport) {
    let (status, detail) = match &report.outcome {
        Outcome::Ran { headline } => ("ran", headline.as_str()),
        Outcome::UpToDate => ("up to date", ""),
        Outcome::Skipped => ("skipped", ""),
    };
    println!("{:<10} {:<11} {:>7.2} s  {detail}", report.stage.name(), status, report.seconds);
}

/// The default output folder of a scene: `out/<scene name>`.
pub fn default_out(scene: &Scene) -> PathBuf {
    PathBuf::from("out").join(&scene.name)
}
