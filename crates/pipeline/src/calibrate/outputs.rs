//! What a calibration writes into its output folder:
//!
//! - `calibrated.toml`: the scene with the best candidate's values, ready to run;
//! - `report.json`: the target, the box with the values before and after, each metric's target,
//!   before, after and real-cave range, the distances and the budget spent;
//! - `report.png`: the same metrics drawn ([`super::chart`]);
//! - `iterations.csv`: one row per candidate: generation, index in it, step size σ, distance,
//!   parameter values, the metrics (medians over the seeds) and why it failed, if it did.
//!
//! Nothing here depends on the clock, so that the files are byte-identical between runs.

use std::fmt::Write as _;
use std::path::Path;

use serde::Serialize;

use karst_metrics::ranges::{CHARACTERIZE_KEYS, real_cave_ranges};
use karst_scene::params::CalibrateParams;
use karst_stage::StageError;

use super::Evaluated;
use super::chart;
use super::evaluate::MetricVector;
use super::scene_edit::{Setting, calibrated_text};
use super::space::Space;
use super::target::{Aim, Target};
use crate::scene::SceneFile;

/// One candidate evaluated.
pub struct Candidate {
    /// 0 for the scene itself, then CMA-ES generations from 1.
    pub generation: usize,
    pub index: usize,
    /// The step size of the generation.
    pub sigma: f64,
    /// Its parameter values (None: unset in the scene).
    pub values: Vec<Option<f64>>,
    pub evaluated: Evaluated,
}

/// A finished calibration.
pub struct Outcome<'a> {
    pub scene: &'a SceneFile,
    /// The scene's text, which the calibrated scene edits.
    pub scene_text: &'a str,
    /// The aim given on the command line (None: the scene's own), recorded in the calibrated
    /// scene's `[calibrate]` so that its runs report against it.
    pub aim: Option<&'a Aim>,
    pub config: &'a CalibrateParams,
    pub space: &'a Space,
    pub target: &'a Target,
    pub seeds: &'a [u64],
    /// Every candidate, the scene itself first.
    pub candidates: &'a [Candidate],
    pub generations: usize,
    pub population: usize,
    /// Which budget ended the search.
    pub stopped_by: &'static str,
}

impl Outcome<'_> {
    /// The scene itself.
    pub fn before(&self) -> &Candidate {
        &self.candidates[0]
    }

    /// The candidate of least distance (the earliest of equals).
    pub fn best(&self) -> &Candidate {
        self.candidates
            .iter()
            .reduce(|best, c| if c.evaluated.distance < best.evaluated.distance { c } else { best })
            .expect("the scene itself is a candidate")
    }
}

/// Writes the four outputs into `out`.
pub fn write(out: &Path, outcome: &Outcome) -> Result<(), StageError> {
    let failure =
        |path: &Path, e: &dyn std::fmt::Display| StageError::failure(format!("{}: {e}", path.display()));
    std::fs::create_dir_all(out).map_err(|e| failure(out, &e))?;
    let write = |name: &str, bytes: &[u8]| {
        let path = out.join(name);
        karst_artifact::atomic::write_bytes(&path, bytes).map_err(|e| failure(&path, &e))
    };
    let calibrated = calibrated_text(
        outcome.scene_text,
        &outcome.scene.path,
        &settings(outcome),
        aim_setting(outcome.aim).as_ref(),
        &header(outcome),
    )
    .map_err(|e| failure(&out.join("calibrated.toml"), &e))?;
    write("calibrated.toml", calibrated.as_bytes())?;
    let report = serde_json::to_string_pretty(&report(outcome)).map_err(|e| failure(out, &e))? + "\n";
    write("report.json", report.as_bytes())?;
    let title = format!(
        "Calibration to {}: distance {} → {}",
        file_name(&outcome.target.name),
        karst_plot::ticks::human(outcome.before().evaluated.distance),
        karst_plot::ticks::human(outcome.best().evaluated.distance)
    );
    let canvas = chart::draw(
        &title,
        &outcome.target.metrics,
        &outcome.before().evaluated.metrics,
        &outcome.best().evaluated.metrics,
    );
    let mut png = Vec::new();
    canvas.encode_png(&mut png).map_err(|e| failure(&out.join("report.png"), &e))?;
    write("report.png", &png)?;
    write("iterations.csv", log(outcome).as_bytes())
}

fn file_name(path: &str) -> String {
    Path::new(path).file_name().map_or(path.to_string(), |f| f.to_string_lossy().into_owned())
}

/// The best candidate's values, as scene settings.
fn settings<'a>(outcome: &'a Outcome) -> Vec<Setting<'a>> {
    outcome
        .space
        .dimensions
        .iter()
        .zip(&outcome.best().values)
        .filter_map(|(d, v)| v.map(|value| Setting { name: d.parameter.name, value, integer: d.integer }))
        .collect()
}

/// The `[calibrate]` field that records `aim` and its value: `like`, or `target` made absolute
/// (a pair of CSV files has no place in the scene: None).
fn aim_setting(aim: Option<&Aim>) -> Option<(&'static str, String)> {
    match aim? {
        Aim::Like(name) => Some(("like", name.clone())),
        Aim::Cave(files) => match files.as_slice() {
            [file] => {
                Some(("target", std::path::absolute(file).unwrap_or(file.clone()).display().to_string()))
            }
            _ => None,
        },
    }
}

fn header(outcome: &Outcome) -> String {
    format!(
        "# Calibrated by `karstgen calibrate` to {}: distance {} → {} (median over seeds {:?}).\n",
        file_name(&outcome.target.name),
        outcome.before().evaluated.distance,
        outcome.best().evaluated.distance,
        outcome.seeds
    )
}

#[derive(Serialize)]
struct Report<'a> {
    scene: String,
    target: &'a str,
    seeds: &'a [u64],
    calibrate: &'a CalibrateParams,
    stopped_by: &'static str,
    candidates: usize,
    generations: usize,
    population: usize,
    distance: Distance,
    best: Position,
    parameters: Vec<ParameterRow<'a>>,
    metrics: Vec<MetricRow>,
}

#[derive(Serialize)]
struct Distance {
    before: f64,
    after: f64,
    /// 1 − after / before.
    reduction: f64,
}

#[derive(Serialize)]
struct Position {
    generation: usize,
    index: usize,
}

#[derive(Serialize)]
struct ParameterRow<'a> {
    name: &'a str,
    min: f64,
    max: f64,
    integer: bool,
    before: Option<f64>,
    after: Option<f64>,
}

#[derive(Serialize)]
struct MetricRow {
    name: &'static str,
    target: Option<f64>,
    before: Option<f64>,
    after: Option<f64>,
    real_caves_min: f64,
    real_caves_max: f64,
}

fn report<'a>(outcome: &'a Outcome) -> Report<'a> {
    let (before, best) = (outcome.before(), outcome.best());
    let finite = |v: f64| v.is_finite().then_some(v);
    let ranges = real_cave_ranges();
    Report {
        scene: outcome.scene.path.display().to_string(),
        target: &outcome.target.name,
        seeds: outcome.seeds,
        calibrate: outcome.config,
        stopped_by: outcome.stopped_by,
        candidates: outcome.candidates.len(),
        generations: outcome.generations,
        population: outcome.population,
        distance: Distance {
            before: before.evaluated.distance,
            after: best.evaluated.distance,
            reduction: 1.0 - best.evaluated.distance / before.evaluated.distance,
        },
        best: Position { generation: best.generation, index: best.index },
        parameters: outcome
            .space
            .dimensions
            .iter()
            .enumerate()
            .map(|(i, d)| ParameterRow {
                name: d.parameter.name,
                min: d.min,
                max: d.max,
                integer: d.integer,
                before: before.values[i],
                after: best.values[i],
            })
            .collect(),
        metrics: CHARACTERIZE_KEYS
            .iter()
            .enumerate()
            .map(|(i, &name)| MetricRow {
                name,
                target: finite(outcome.target.metrics[i]),
                before: finite(before.evaluated.metrics[i]),
                after: finite(best.evaluated.metrics[i]),
                real_caves_min: ranges[name].min,
                real_caves_max: ranges[name].max,
            })
            .collect(),
    }
}

/// `iterations.csv`.
fn log(outcome: &Outcome) -> String {
    let mut columns = vec!["generation", "candidate", "sigma", "distance"];
    columns.extend(outcome.space.dimensions.iter().map(|d| d.parameter.name));
    columns.extend(CHARACTERIZE_KEYS);
    columns.push("failure");
    let mut out = columns.iter().map(|c| format!("\"{c}\"")).collect::<Vec<_>>().join(",") + "\n";
    let show = |v: f64| if v.is_finite() { v.to_string() } else { String::new() };
    for c in outcome.candidates {
        let mut cells =
            vec![c.generation.to_string(), c.index.to_string(), show(c.sigma), show(c.evaluated.distance)];
        cells.extend(c.values.iter().map(|v| v.map_or(String::new(), show)));
        cells.extend(metric_cells(&c.evaluated.metrics, show));
        cells.push(
            c.evaluated
                .failure
                .as_ref()
                .map_or(String::new(), |f| format!("\"{}\"", f.to_string().replace('"', "'"))),
        );
        let _ = writeln!(out, "{}", cells.join(","));
    }
    out
}

fn metric_cells(metrics: &MetricVector, show: impl Fn(f64) -> String) -> Vec<String> {
    metrics.iter().map(|&m| show(m)).collect()
}
