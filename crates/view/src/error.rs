//! What can go wrong when writing or serving a view. Every message names the folder, file or
//! port and says what to do; [`ViewError::exit_code`] follows karstgen's contract (2: bad
//! input, 1: a failure of karstgen or of the machine).

use std::path::PathBuf;

/// An error of [`crate::write_view`] or [`crate::Server`].
#[derive(Debug, thiserror::Error)]
pub enum ViewError {
    #[error("{dir}: no such folder: give the output folder of a run (`karstgen run SCENE --out DIR`)")]
    NoFolder { dir: PathBuf },
    #[error(
        "{dir}: not a karstgen run (none of {expected} is there): run `karstgen run SCENE --out {dir}` \
         first, then view that folder"
    )]
    NotARun { dir: PathBuf, expected: String },
    #[error("{dir}: has no view/index.html: write the view first (`karst-view {run}`)")]
    NoView { dir: PathBuf, run: String },
    #[error(transparent)]
    Scene(#[from] karst_scene::SceneError),
    /// The run folder cannot be locked: another process writes into it, or it is not writable.
    #[error(transparent)]
    Lock(#[from] karst_artifact::Error),
    #[error("{path}: cannot write: {source}")]
    Write { path: PathBuf, source: std::io::Error },
    #[error("{path}: cannot encode the {what}: {detail}")]
    Encode { path: PathBuf, what: String, detail: String },
    #[error(
        "port {port} on 127.0.0.1 is in use (another server is running?): choose another one with \
         --port {suggestion}, or --port 0 for any free port"
    )]
    PortInUse { port: u16, suggestion: u16 },
    #[error("cannot listen on 127.0.0.1:{port}: {source}")]
    Listen { port: u16, source: std::io::Error },
}

impl ViewError {
    /// The process exit code: 2 for bad input (the folder, the scene, the port), 1 otherwise.
    pub fn exit_code(&self) -> u8 {
        match self {
            ViewError::NoFolder { .. }
            | ViewError::NotARun { .. }
            | ViewError::NoView { .. }
            | ViewError::Scene(_)
            | ViewError::PortInUse { .. } => 2,
            ViewError::Write { .. } | ViewError::Encode { .. } | ViewError::Listen { .. } => 1,
            ViewError::Lock(e) => {
                if e.is_bad_input() {
                    2
                } else {
                    1
                }
            }
        }
    }
}
