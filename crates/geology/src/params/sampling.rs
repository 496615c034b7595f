//! `[sampling]`: Poisson-disk sampling of the bedrock.

use serde::{Deserialize, Serialize};

use crate::validate::Checks;

#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct SamplingParams {
    /// Minimum distance between two samples, metres.
    pub radius: f64,
    /// Candidates tried around each active sample before it retires (Bridson's k).
    pub attempts: u32,
}

impl Default for SamplingParams {
    fn default() -> Self {
        SamplingParams { radius: 20.0, attempts: 30 }
    }
}

impl SamplingParams {
    pub(crate) fn check(&self, c: &mut Checks) {
        c.positive("sampling.radius", self.radius);
        if self.attempts == 0 {
            c.report("sampling.attempts", "must be ≥ 1".into());
        }
    }
}
