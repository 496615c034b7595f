//! What can stop an export: an input missing from the run or artifacts that do not belong
//! together (the user's to fix, exit code 2), or a folder that cannot be written.

use std::path::PathBuf;

use karst_stage::{Blame, Failure};

#[derive(Debug, thiserror::Error)]
pub enum ExportError {
    #[error("format `{format}` needs {input}: run the stages that write it first (`karstgen run`)")]
    MissingInput { format: &'static str, input: &'static str },
    #[error("{0}")]
    Mismatch(String),
    #[error("{path}: cannot write: {source}")]
    Write { path: PathBuf, source: std::io::Error },
    #[error("{0}")]
    Unsupported(String),
}

impl Failure for ExportError {
    fn blame(&self) -> Blame {
        match self {
            ExportError::Write { .. } => Blame::Internal,
            ExportError::Mismatch(_) => Blame::Artifact(karst_artifact::StageId::Hydro),
            ExportError::MissingInput { .. } | ExportError::Unsupported(_) => Blame::Scene,
        }
    }
}
