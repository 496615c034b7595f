//! The error of a command-line option the pipeline reads (`--seeds`, `--n`, `--keep`, `--cell`,
//! `--budget`): typed, and naming the option, the value given and what is wrong with it, so
//! that the command refuses it (exit 2) with a message the user can act on.

/// An option's value that cannot be used.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[error("{option} \"{value}\": {problem}")]
pub struct OptionError {
    /// The option, with its dashes (`--seeds`).
    pub option: &'static str,
    pub value: String,
    pub problem: String,
}

impl OptionError {
    /// `value` of `option` is wrong because of `problem`.
    pub fn new(option: &'static str, value: impl ToString, problem: impl Into<String>) -> Self {
        OptionError { option, value: value.to_string(), problem: problem.into() }
    }
}
