//! Errors of the artifact layer, and the error every stage binary reports.
//!
//! I/O errors keep the operating system's error as their source: the stage binaries print the
//! whole chain ("FILE: cannot read: No such file or directory").
//!
//! Exit codes are part of karstgen's command-line contract: 2 for bad input (a scene, an
//! artifact or a network file that is wrong), 1 for a failure of karstgen itself or of the
//! machine (a write that fails, an internal invariant).

use std::path::PathBuf;

/// What can go wrong when reading or writing an artifact. Every message names the file.
#[derive(Debug, thiserror::Error)]
pub enum Error {
    #[error("{path}: cannot read")]
    Open { path: PathBuf, source: std::io::Error },
    #[error("{path}: cannot write")]
    Write { path: PathBuf, source: std::io::Error },
    #[error("{path}: not a karstgen artifact ({detail})")]
    NotAnArtifact { path: PathBuf, detail: String },
    #[error("{path}: is a {found} artifact, expected {expected}")]
    WrongKind { path: PathBuf, found: String, expected: String },
    #[error(
        "{path}: written by {kind} schema {found}, this build reads schema {expected}: \
         rerun `cargo xtask run --from {stage}`"
    )]
    Schema { path: PathBuf, kind: String, found: u32, expected: u32, stage: String },
    #[error(
        "{path}: payload is {found} bytes, the header says {expected} (truncated file?): \
         rerun `cargo xtask run --from {stage}`"
    )]
    Length { path: PathBuf, found: u64, expected: u64, stage: String },
    #[error(
        "{path}: payload checksum mismatch (the file is corrupted): \
         rerun `cargo xtask run --from {stage}`"
    )]
    Checksum { path: PathBuf, stage: String },
    #[error("{path}: cannot decode the {kind} payload ({detail}): rerun `cargo xtask run --from {stage}`")]
    Decode { path: PathBuf, kind: String, detail: String, stage: String },
    #[error("cannot encode the {kind} payload: {detail}")]
    Encode { kind: String, detail: String },
}

impl Error {
    /// True when the error comes from a file the user gave us (exit code 2), false when
    /// karstgen or the machine failed (exit code 1).
    pub fn is_bad_input(&self) -> bool {
        !matches!(self, Error::Write { .. } | Error::Encode { .. })
    }
}

/// The error of a stage run: bad input (exit 2) or a failure (exit 1), with a message that
/// already carries its context.
#[derive(Debug, thiserror::Error)]
pub enum StageError {
    #[error("{0:#}")]
    BadInput(anyhow::Error),
    #[error("{0:#}")]
    Failure(anyhow::Error),
}

impl StageError {
    /// Bad input, with a message.
    pub fn input(message: impl std::fmt::Display) -> Self {
        StageError::BadInput(anyhow::anyhow!("{message}"))
    }

    /// A failure, with a message.
    pub fn failure(message: impl std::fmt::Display) -> Self {
        StageError::Failure(anyhow::anyhow!("{message}"))
    }

    /// The process exit code for this error.
    pub fn exit_code(&self) -> u8 {
        match self {
            StageError::BadInput(_) => 2,
            StageError::Failure(_) => 1,
        }
    }
}

impl From<Error> for StageError {
    fn from(e: Error) -> Self {
        if e.is_bad_input() { StageError::BadInput(e.into()) } else { StageError::Failure(e.into()) }
    }
}
