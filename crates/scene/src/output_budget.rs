//! The output budget of a run: the bytes its meshes and exports may take (`karstgen run
//! --budget MB`, `karstgen export --budget MB`). The mesher's and the export's estimates are
//! held against it before they write anything; it is a property of the run, not of the scene,
//! and is in no artifact key. MB are MiB ([`MB`]), as in every size karstgen prints.

use std::str::FromStr;

use crate::budget::MB;

/// The default budget of the meshes and the exports together, MB: what `karstgen run` and
/// `karstgen export` allow without `--budget`.
pub const DEFAULT_OUTPUT_MB: f64 = 300.0;

/// Bytes the meshes (mesh.bin) and the exports of a run may take.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct OutputBudget {
    pub bytes: f64,
}

impl Default for OutputBudget {
    fn default() -> Self {
        OutputBudget { bytes: DEFAULT_OUTPUT_MB * MB }
    }
}

/// A `--budget` that cannot be used.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[error("\"{0}\" is not a budget: give a number of MB above 0")]
pub struct OutputBudgetError(pub String);

impl OutputBudget {
    /// A budget of `megabytes` MB; refused unless finite and above 0.
    pub fn megabytes(megabytes: f64) -> Result<OutputBudget, OutputBudgetError> {
        if megabytes.is_finite() && megabytes > 0.0 {
            Ok(OutputBudget { bytes: megabytes * MB })
        } else {
            Err(OutputBudgetError(megabytes.to_string()))
        }
    }
}

impl FromStr for OutputBudget {
    type Err = OutputBudgetError;

    /// A number of MB, as given to `--budget`.
    fn from_str(text: &str) -> Result<OutputBudget, OutputBudgetError> {
        let megabytes = text.trim().parse::<f64>().map_err(|_| OutputBudgetError(text.into()))?;
        OutputBudget::megabytes(megabytes).map_err(|_| OutputBudgetError(text.into()))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn budgets_are_positive_numbers_of_mb() {
        assert_eq!("1.5".parse::<OutputBudget>().unwrap().bytes, 1.5 * MB);
        assert_eq!(OutputBudget::default().bytes, 300.0 * MB);
        for bad in ["0", "-3", "lots", "inf", "NaN", ""] {
            let err = bad.parse::<OutputBudget>().unwrap_err().to_string();
            assert!(err.contains(&format!("\"{bad}\"")) && err.contains("above 0"), "{err}");
        }
    }
}
