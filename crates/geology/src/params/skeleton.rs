//! `[skeleton]`: the conduit network.

use serde::{Deserialize, Serialize};

use crate::validate::Checks;

#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct SkeletonParams {
    /// Range `[min, max]` of conduit radii, metres; each conduit draws its radius uniformly.
    pub radius: [f64; 2],
}

impl Default for SkeletonParams {
    fn default() -> Self {
        SkeletonParams { radius: [0.5, 4.0] }
    }
}

impl SkeletonParams {
    pub(crate) fn check(&self, c: &mut Checks) {
        let [lo, hi] = self.radius;
        c.positive("skeleton.radius", lo);
        if lo.is_finite() && hi.is_finite() && hi < lo {
            c.report("skeleton.radius", format!("[{lo}, {hi}] is not a range (max < min)"));
        }
    }
}
