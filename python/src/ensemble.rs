//! Ensembles from Python: the same plan, realizations, records and summary as `karstgen
//! ensemble` (crates/pipeline/src/ensemble), so that a folder written by Dask workers and one
//! written by the command line are interchangeable (and mergeable).
//!
//! Every function takes the plan's parts (scene path and text, folder, stage, cell, kept
//! artifacts), which are plain values a Dask task can carry to another machine.

use std::path::{Path, PathBuf};

use pyo3::prelude::*;
use pyo3::types::{PyBytes, PyDict};

use karst_pipeline::ensemble::{self, Keep, Outcome, Plan, Record};
use karst_pipeline::scene::SceneFile;
use karst_scene::Scene;
use karst_stage::StageError;

use crate::errors::{argument, to_py};
use crate::run::{stage_named, with_threads};

/// The parts of a plan, as Python passes them.
struct PlanArgs<'a> {
    path: &'a Path,
    text: &'a str,
    until: Option<&'a str>,
    cell: f64,
    keep: &'a [String],
}

impl PlanArgs<'_> {
    fn plan(&self) -> PyResult<Plan> {
        let to = match self.until {
            None => Some(ensemble::DEFAULT_TO),
            Some("all") => None,
            Some(name) => stage_named(Some(name))?,
        };
        let keep = Keep::parse(&self.keep.join(",")).map_err(argument)?;
        let scene = Scene::parse(self.text, self.path).map_err(|e| to_py(e.into()))?;
        Plan::new(SceneFile { path: self.path.to_path_buf(), scene }, to, self.cell, keep).map_err(to_py)
    }
}

/// Makes `out` the plan's ensemble folder (or checks that it is); returns the plan's key.
#[pyfunction]
#[pyo3(signature = (path, text, out, until, cell, keep))]
pub fn ensemble_prepare(
    py: Python<'_>,
    path: PathBuf,
    text: String,
    out: PathBuf,
    until: Option<String>,
    cell: f64,
    keep: Vec<String>,
) -> PyResult<String> {
    let plan = PlanArgs { path: &path, text: &text, until: until.as_deref(), cell, keep: &keep }.plan()?;
    py.detach(|| plan.prepare(&out)).map_err(to_py)?;
    Ok(plan.key())
}

/// The seeds of `seeds` whose realization still needs work in `out`.
#[pyfunction]
#[pyo3(signature = (path, text, out, until, cell, keep, seeds))]
#[allow(clippy::too_many_arguments)]
pub fn ensemble_pending(
    py: Python<'_>,
    path: PathBuf,
    text: String,
    out: PathBuf,
    until: Option<String>,
    cell: f64,
    keep: Vec<String>,
    seeds: Vec<u64>,
) -> PyResult<Vec<u64>> {
    let plan = PlanArgs { path: &path, text: &text, until: until.as_deref(), cell, keep: &keep }.plan()?;
    Ok(py.detach(|| plan.pending(&out, &seeds)))
}

/// Runs one realization (a Dask task) on `threads` threads and writes its record; returns
/// `(seed, error)`, `error` None when complete. Raises only when the record cannot be written.
#[pyfunction]
#[pyo3(signature = (path, text, out, until, cell, keep, seed, threads=1))]
#[allow(clippy::too_many_arguments)]
pub fn realize(
    py: Python<'_>,
    path: PathBuf,
    text: String,
    out: PathBuf,
    until: Option<String>,
    cell: f64,
    keep: Vec<String>,
    seed: u64,
    threads: Option<usize>,
) -> PyResult<(u64, Option<String>)> {
    let plan = PlanArgs { path: &path, text: &text, until: until.as_deref(), cell, keep: &keep }.plan()?;
    let record =
        py.detach(|| with_threads(threads, || ensemble::realize(&plan, &out, seed))).map_err(to_py)?;
    Ok(match record.outcome {
        Outcome::Complete(_) => (seed, None),
        Outcome::Failed { error, .. } => (seed, Some(error)),
    })
}

/// Records that the realization of `seed` failed outside karstgen (its worker died): a
/// failure tried again by the next run.
#[pyfunction]
pub fn record_failure(py: Python<'_>, out: PathBuf, key: String, seed: u64, error: String) -> PyResult<()> {
    let record = Record { seed, key, outcome: Outcome::Failed { error, retry: true } };
    py.detach(|| record.write(&out))
        .map_err(|e| to_py(StageError::failure(format!("{}: {e}", Record::path(&out, seed).display()))))
}

/// Writes the summary outputs of the folder `out` and returns them: `complete`, `failures`
/// (seed, error), `columns`, `rows` (float64 bytes, row-major), `grid` (min, cell, dims) and
/// `counts` (uint32 bytes, x fastest).
/// `depth_band` (min, max), metres below ground, limits `probability.tif` to the conduits in
/// that band.
#[pyfunction]
#[pyo3(signature = (out, depth_band=None))]
pub fn ensemble_summarize<'py>(
    py: Python<'py>,
    out: PathBuf,
    depth_band: Option<(f64, f64)>,
) -> PyResult<Bound<'py, PyDict>> {
    let band = match depth_band {
        Some((min, max)) => Some(ensemble::parse_depth_band(&format!("{min}..{max}")).map_err(argument)?),
        None => None,
    };
    let summary = py.detach(|| ensemble::summarize(&out, band)).map_err(to_py)?;
    let dict = PyDict::new(py);
    let rows: Vec<u8> = summary.table.rows.iter().flatten().flat_map(|v| v.to_le_bytes()).collect();
    let counts: Vec<u8> = summary.counts.iter().flat_map(|c| c.to_le_bytes()).collect();
    dict.set_item("complete", summary.complete)?;
    dict.set_item("failures", summary.failures)?;
    dict.set_item("columns", summary.table.columns)?;
    dict.set_item("rows", PyBytes::new(py, &rows))?;
    dict.set_item("grid", (summary.grid.min, summary.grid.cell, summary.grid.dims))?;
    dict.set_item("counts", PyBytes::new(py, &counts))?;
    Ok(dict)
}

/// The seeds of a `--seeds` text: `100..200` (end excluded), `100..=199`, `1,5,7`, mixes.
#[pyfunction]
pub fn parse_seeds(spec: &str) -> PyResult<Vec<u64>> {
    ensemble::parse_seeds(spec).map_err(argument)
}
