//! Why a candidate cannot be evaluated or the calibrated scene cannot be written.

/// A calibration error: a stage that fails on a candidate's scene, or a calibrated scene that
/// cannot be edited or does not validate.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum CalibrateError {
    /// A stage (sampling, costgraph, skeleton, metrics) failed on a candidate's scene.
    #[error("{stage}: {message}")]
    Stage { stage: &'static str, message: String },
    /// The scene text cannot be parsed as TOML for editing.
    #[error("the scene is not valid TOML: {0}")]
    Toml(String),
    /// A calibrated parameter not written `section.field`.
    #[error("{0}: not section.field")]
    NotSectionField(String),
    /// The section a calibrated parameter belongs to is not a table in the scene text.
    #[error("[{0}] is not a table")]
    NotATable(String),
    /// The calibrated scene does not parse or validate as a scene.
    #[error("the calibrated scene does not validate: {0}")]
    Invalid(String),
}

impl CalibrateError {
    /// `stage` failed with `error`.
    pub fn stage(stage: &'static str, error: impl std::fmt::Display) -> CalibrateError {
        CalibrateError::Stage { stage, message: error.to_string() }
    }

    /// The stage called `name` failed with `message` (a failure reported from another process).
    pub fn stage_named(name: &str, message: String) -> CalibrateError {
        let stage = ["sampling", "costgraph", "skeleton", "metrics"]
            .into_iter()
            .find(|s| *s == name)
            .unwrap_or("candidate");
        CalibrateError::Stage { stage, message }
    }
}
