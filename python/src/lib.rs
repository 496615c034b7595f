//! `karstgen._native`: the Rust side of the Python package `karstgen`.
//!
//! Thin functions over the workspace's library crates (no subprocess, no stage binary): the
//! Python modules in `karstgen/` shape their results into NumPy arrays, pandas DataFrames and
//! Dask tasks. Arrays cross as `bytes` in native byte order (`numpy.frombuffer`), so values
//! are the artifacts' bit for bit.
//!
//! - `errors.rs`: karstgen's errors as Python exceptions (`SceneError`, `ArtifactError`,
//!   `KarstgenError`);
//! - `scene.rs`: a scene from a file or a dict, with overrides, checked;
//! - `run.rs`: the pipeline in a worker thread, the GIL released, Ctrl-C honoured;
//! - `artifacts.rs`: a run's network, meshes, JSON payloads and figures;
//! - `metrics.rs`: karstnet's statistics of any network;
//! - `ensemble.rs`: one realization (a Dask task), the folder's plan and its summary;
//! - `calibrate.rs`: the calibration's search steps, and one candidate on one seed (a Dask task).

use pyo3::prelude::*;

mod artifacts;
mod calibrate;
mod ensemble;
mod errors;
mod metrics;
mod run;
mod scene;

#[pymodule]
fn _native(m: &Bound<'_, PyModule>) -> PyResult<()> {
    let py = m.py();
    m.add("KarstgenError", py.get_type::<errors::KarstgenError>())?;
    m.add("SceneError", py.get_type::<errors::SceneError>())?;
    m.add("ArtifactError", py.get_type::<errors::ArtifactError>())?;
    m.add("VERSION", env!("CARGO_PKG_VERSION"))?;
    m.add("STAGES", karst_artifact::StageId::ALL.map(|s| s.name()).to_vec())?;
    m.add("STAGE_FILES", karst_artifact::StageId::ALL.map(|s| (s.name(), s.file_name())).to_vec())?;
    m.add_function(wrap_pyfunction!(scene::scene_source, m)?)?;
    m.add_function(wrap_pyfunction!(run::run, m)?)?;
    m.add_function(wrap_pyfunction!(artifacts::read_network, m)?)?;
    m.add_function(wrap_pyfunction!(artifacts::read_mesh, m)?)?;
    m.add_function(wrap_pyfunction!(artifacts::read_payload, m)?)?;
    m.add_function(wrap_pyfunction!(artifacts::figures, m)?)?;
    m.add_function(wrap_pyfunction!(metrics::characterize, m)?)?;
    m.add_function(wrap_pyfunction!(ensemble::ensemble_prepare, m)?)?;
    m.add_function(wrap_pyfunction!(ensemble::ensemble_pending, m)?)?;
    m.add_function(wrap_pyfunction!(ensemble::realize, m)?)?;
    m.add_function(wrap_pyfunction!(ensemble::record_failure, m)?)?;
    m.add_function(wrap_pyfunction!(ensemble::ensemble_summarize, m)?)?;
    m.add_function(wrap_pyfunction!(ensemble::parse_seeds, m)?)?;
    m.add_class::<calibrate::Calibration>()?;
    m.add_function(wrap_pyfunction!(calibrate::calibrate_evaluate, m)?)?;
    Ok(())
}
