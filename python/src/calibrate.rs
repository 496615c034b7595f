//! Calibration from Python: the Rust search's steps (crates/pipeline/src/calibrate/search.rs),
//! so that `karstgen.calibrate` runs the same CMA-ES as `karstgen calibrate` while its
//! candidates run wherever Python sends them (Dask tasks, or this process).
//!
//! - [`Calibration`]: the search itself, held by the calling process: `ask` gives the next
//!   generation's parameter values, `tell` takes their metrics, `finish` writes the outputs;
//! - [`calibrate_evaluate`]: one candidate on one seed to its ten metrics, from plain values a
//!   Dask task can carry (scene path and text, parameter names and values, seed). The stages
//!   the box leaves alone are computed once per scene and seed in each process and kept.

use std::collections::HashMap;
use std::path::PathBuf;
use std::sync::{Arc, Mutex};

use pyo3::prelude::*;

use karst_pipeline::calibrate::{Aim, CalibrateError, MetricVector, Runner, Search};
use karst_pipeline::scene::SceneFile;
use karst_scene::params::parameter;
use karst_scene::{Scene, Section};
use karst_stage::StageError;

use crate::errors::{argument, to_py};
use crate::run::with_threads;

/// One candidate's result on one seed as Python carries it: the ten metrics (NaN: undefined),
/// or the stage that failed and its message.
#[derive(IntoPyObject, FromPyObject)]
pub enum RunResult {
    Metrics(Vec<f64>),
    Failed(String, String),
}

/// A calibration in progress (the Rust [`Search`], CMA-ES).
#[pyclass(module = "karstgen._native")]
pub struct Calibration {
    search: Mutex<Search>,
}

fn locked(c: &Calibration) -> std::sync::MutexGuard<'_, Search> {
    c.search.lock().unwrap_or_else(|e| e.into_inner())
}

#[pymethods]
impl Calibration {
    /// The calibration of the scene `text` (named `path`) towards `like` (a published network),
    /// `target` (one cave file, or two CSV files), or the target its `[calibrate]` names.
    #[new]
    #[pyo3(signature = (path, text, like=None, target=None))]
    fn new(
        path: PathBuf,
        text: String,
        like: Option<String>,
        target: Option<Vec<PathBuf>>,
    ) -> PyResult<Self> {
        let aim = match (like, target) {
            (Some(_), Some(_)) => return Err(argument("calibrate: give like or target, not both")),
            (Some(name), None) => Some(Aim::Like(name)),
            (None, Some(files)) => Some(Aim::Cave(files)),
            (None, None) => None,
        };
        let scene = SceneFile::parse(&text, &path).map_err(to_py)?;
        let search = Search::new(scene, text, aim).map_err(to_py)?;
        Ok(Calibration { search: Mutex::new(search) })
    }

    /// The seeds every candidate runs on.
    #[getter]
    fn seeds(&self) -> Vec<u64> {
        locked(self).seeds().to_vec()
    }

    /// The parameters searched (`section.field`), in the box's order.
    #[getter]
    fn names(&self) -> Vec<&'static str> {
        locked(self).names()
    }

    /// The next generation's parameter values (None: the scene itself, the first generation),
    /// or None when the budget is spent.
    fn ask(&self) -> Option<Vec<Option<Vec<f64>>>> {
        locked(self).ask_values()
    }

    /// Runs `candidates` (as [`Calibration::ask`] gave them) on every seed in this process, on
    /// `threads` threads (None: all cores); `[candidate][seed]`.
    #[pyo3(signature = (candidates, threads=None))]
    fn evaluate(
        &self,
        py: Python<'_>,
        candidates: Vec<Option<Vec<f64>>>,
        threads: Option<usize>,
    ) -> PyResult<Vec<Vec<RunResult>>> {
        let mut search = locked(self);
        let scenes: Vec<Scene> = candidates.iter().map(|v| search.scene_of(v.as_deref())).collect();
        let runner = search.runner().map_err(to_py)?;
        let runs = py.detach(|| with_threads(threads, || Ok(runner.run(&scenes, &|| {})))).map_err(to_py)?;
        Ok(runs.into_iter().map(|seeds| seeds.into_iter().map(to_result).collect()).collect())
    }

    /// The metrics of the generation last asked, `[candidate][seed]`.
    fn tell(&self, runs: Vec<Vec<RunResult>>) -> PyResult<()> {
        let runs = runs.into_iter().map(from_result).collect::<PyResult<Vec<_>>>()?;
        locked(self).tell(runs).map_err(to_py)
    }

    /// Writes `calibrated.toml`, `report.json`, `report.png` and `iterations.csv` into `out`
    /// (as `karstgen calibrate` does) and returns the summary and the best scene's verdict.
    fn finish(&self, py: Python<'_>, out: PathBuf) -> PyResult<String> {
        let mut guard = locked(self);
        let search: &mut Search = &mut guard;
        py.detach(|| search.finish(&out)).map_err(to_py)
    }
}

fn to_result(run: Result<MetricVector, CalibrateError>) -> RunResult {
    match run {
        Ok(metrics) => RunResult::Metrics(metrics.to_vec()),
        Err(CalibrateError::Stage { stage, message }) => RunResult::Failed(stage.to_string(), message),
        Err(other) => RunResult::Failed("candidate".into(), other.to_string()),
    }
}

fn from_result(run: Vec<RunResult>) -> PyResult<Vec<Result<MetricVector, CalibrateError>>> {
    run.into_iter()
        .map(|r| match r {
            RunResult::Metrics(values) => MetricVector::try_from(values.as_slice())
                .map(Ok)
                .map_err(|_| argument(format!("a run has {} metrics, not 10", values.len()))),
            RunResult::Failed(stage, message) => Ok(Err(CalibrateError::stage_named(&stage, message))),
        })
        .collect()
}

/// The runners this process prepared: one per (scene, box sections, seed), a few kept.
type Runners = Mutex<HashMap<(String, u64), Arc<Runner>>>;

static RUNNERS: std::sync::OnceLock<Runners> = std::sync::OnceLock::new();

/// At most this many prepared (scene, seed) pairs are kept per process.
const KEPT: usize = 64;

fn runner(
    path: &std::path::Path,
    text: &str,
    scene: &Scene,
    sections: &[Section],
    seed: u64,
) -> Result<Arc<Runner>, StageError> {
    let key = (format!("{}\n{sections:?}\n{text}", path.display()), seed);
    let runners = RUNNERS.get_or_init(Default::default);
    if let Some(r) = runners.lock().unwrap_or_else(|e| e.into_inner()).get(&key) {
        return Ok(Arc::clone(r));
    }
    let prepared = Arc::new(
        Runner::new(scene, vec![seed], sections)
            .map_err(|e| StageError::input(format!("{}: {e}", path.display())))?,
    );
    let mut kept = runners.lock().unwrap_or_else(|e| e.into_inner());
    if kept.len() >= KEPT {
        kept.clear();
    }
    kept.insert(key, Arc::clone(&prepared));
    Ok(prepared)
}

/// One candidate on one seed (a Dask task): the scene `text` (named `path`) with the parameters
/// `names` set to `values` (None: the scene itself), run through sampling, cost graph and
/// skeleton in memory on `threads` threads, to karstnet's ten metrics, or the stage that failed.
#[pyfunction]
#[pyo3(signature = (path, text, names, values, seed, threads=1))]
pub fn calibrate_evaluate(
    py: Python<'_>,
    path: PathBuf,
    text: String,
    names: Vec<String>,
    values: Option<Vec<f64>>,
    seed: u64,
    threads: Option<usize>,
) -> PyResult<RunResult> {
    let base = Scene::parse(&text, &path).map_err(|e| to_py(e.into()))?;
    let parameters = names
        .iter()
        .map(|n| parameter(n).ok_or_else(|| argument(format!("unknown calibration parameter \"{n}\""))))
        .collect::<PyResult<Vec<_>>>()?;
    let mut candidate = base.clone();
    if let Some(values) = &values {
        if values.len() != parameters.len() {
            return Err(argument(format!("{} values for {} parameters", values.len(), parameters.len())));
        }
        for (p, &v) in parameters.iter().zip(values) {
            (p.set)(&mut candidate, v);
        }
    }
    let sections: Vec<Section> = parameters.iter().map(|p| p.section()).collect();
    let run = py
        .detach(|| {
            with_threads(threads, || {
                let prepared = runner(&path, &text, &base, &sections, seed)?;
                Ok(prepared.run(std::slice::from_ref(&candidate), &|| {}).remove(0).remove(0))
            })
        })
        .map_err(to_py)?;
    Ok(to_result(run))
}
