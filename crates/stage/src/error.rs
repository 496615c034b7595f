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

    /// Bad input where the scene (or a data file it names) is at fault.
    pub fn scene(message: impl std::fmt::Display) -> Self {
        StageError::BadInput(anyhow::Error::new(Blamed { input: Input::Scene, message: message.to_string() }))
    }

    /// Bad input where an artifact is at fault.
    pub fn artifact(message: impl std::fmt::Display) -> Self {
        StageError::BadInput(anyhow::Error::new(Blamed {
            input: Input::Artifact,
            message: message.to_string(),
        }))
    }

    /// Which input is at fault, for bad input (callers that tell them apart: the Python
    /// package raises `SceneError` or `ArtifactError`); `None` for a failure.
    pub fn input_at_fault(&self) -> Option<Input> {
        let StageError::BadInput(e) = self else { return None };
        Some(if let Some(blamed) = e.downcast_ref::<Blamed>() {
            blamed.input
        } else if e.downcast_ref::<karst_scene::SceneError>().is_some() {
            Input::Scene
        } else if e.downcast_ref::<karst_artifact::Error>().is_some() {
            Input::Artifact
        } else {
            Input::Other
        })
    }

    /// The process exit code for this error.
    pub fn exit_code(&self) -> u8 {
        match self {
            StageError::BadInput(_) => 2,
            StageError::Failure(_) => 1,
        }
    }
}

/// The input at fault in a [`StageError::BadInput`].
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Input {
    /// The scene file or a data file it names.
    Scene,
    /// An artifact.
    Artifact,
    /// Another file (a network file, an argument).
    Other,
}

/// A bad input's message and which input it blames.
#[derive(Debug, thiserror::Error)]
#[error("{message}")]
struct Blamed {
    input: Input,
    message: String,
}

impl From<karst_artifact::Error> for StageError {
    fn from(e: karst_artifact::Error) -> Self {
        if e.is_bad_input() { StageError::BadInput(e.into()) } else { StageError::Failure(e.into()) }
    }
}

impl From<karst_scene::SceneError> for StageError {
    fn from(e: karst_scene::SceneError) -> Self {
        StageError::BadInput(e.into())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn bad_input_says_which_input_is_at_fault() {
        assert_eq!(StageError::scene("s").input_at_fault(), Some(Input::Scene));
        assert_eq!(StageError::artifact("a").input_at_fault(), Some(Input::Artifact));
        assert_eq!(StageError::input("x").input_at_fault(), Some(Input::Other));
        assert_eq!(StageError::failure("f").input_at_fault(), None);
        let scene = karst_scene::Scene::parse("name = 1", std::path::Path::new("s.toml")).unwrap_err();
        assert_eq!(StageError::from(scene).input_at_fault(), Some(Input::Scene));
        assert_eq!(StageError::scene("line 3: bad").to_string(), "line 3: bad");
    }
}
