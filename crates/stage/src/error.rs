//! The error every stage run and command reports to its user.
//!
//! Exit codes are part of karstgen's command-line contract: 2 for bad input (a scene, an
//! artifact or a network file that is wrong), 1 for a failure of karstgen itself or of the
//! machine (a write that fails, an internal invariant).

/// Bad input (exit 2) or a failure (exit 1), with a message that already carries its context
/// (the file, the field, what to do).
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

impl From<karst_artifact::Error> for StageError {
    fn from(e: karst_artifact::Error) -> Self {
        if e.is_bad_input() { StageError::BadInput(e.into()) } else { StageError::Failure(e.into()) }
    }
}

impl From<karst_geology::SceneError> for StageError {
    fn from(e: karst_geology::SceneError) -> Self {
        StageError::BadInput(e.into())
    }
}
