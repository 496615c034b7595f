//! What can stop an export. Every error is the user's to fix (exit code 2): an input missing
//! from the run, artifacts that do not belong together, or a folder that cannot be written.

use std::path::PathBuf;

#[derive(Debug, thiserror::Error)]
pub enum ExportError {
    #[error("format `{format}` needs {input}: run the stages that write it first (`cargo xtask run`)")]
    MissingInput { format: &'static str, input: &'static str },
    #[error("{0}: rerun `cargo xtask run --from hydro`")]
    Mismatch(String),
    #[error("{path}: cannot write: {source}")]
    Write { path: PathBuf, source: std::io::Error },
    #[error("{0}")]
    Unsupported(String),
}
