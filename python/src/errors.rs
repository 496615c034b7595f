//! karstgen's errors as Python exceptions, never a crash of the interpreter: the scene at
//! fault raises `SceneError`, an artifact `ArtifactError` (both naming the file, line and
//! field as the command line does), any other bad input `ValueError`, a failure of karstgen or
//! of the machine `KarstgenError`.

use pyo3::PyErr;
use pyo3::exceptions::{PyException, PyValueError};

use karst_stage::{Input, StageError};

pyo3::create_exception!(
    karstgen,
    KarstgenError,
    PyException,
    "A failure of karstgen or of the machine (the command line's exit code 1)."
);
pyo3::create_exception!(
    karstgen,
    SceneError,
    KarstgenError,
    "The scene (or a data file it names) is wrong; the message names the file, line and field."
);
pyo3::create_exception!(
    karstgen,
    ArtifactError,
    KarstgenError,
    "An artifact is missing, corrupted or inconsistent; the message says which stage to rerun."
);

/// The Python exception of a karstgen error.
pub fn to_py(e: StageError) -> PyErr {
    let message = e.to_string();
    match e.input_at_fault() {
        Some(Input::Scene) => SceneError::new_err(message),
        Some(Input::Artifact) => ArtifactError::new_err(message),
        Some(Input::Other) => PyValueError::new_err(message),
        None => KarstgenError::new_err(message),
    }
}

/// A bad argument of a Python call.
pub fn argument(message: impl std::fmt::Display) -> PyErr {
    PyValueError::new_err(message.to_string())
}
