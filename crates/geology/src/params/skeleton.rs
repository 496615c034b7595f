//! `[skeleton]`: the conduit network.

use serde::{Deserialize, Serialize};

use crate::validate::Checks;

#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct SkeletonParams {
    /// Range `[min, max]` of conduit radii, metres; each conduit draws its radius uniformly.
    pub radius: [f64; 2],
    /// Segments steeper than this (degrees from horizontal) are shafts: epikarst or tube.
    pub vertical_angle: f64,
    /// Shafts starting within this depth below the ground are epikarst, metres.
    pub epikarst_depth: f64,
    /// Gently sloping vadose segments within this height above the water table are keyholes.
    pub keyhole_height: f64,
}

impl Default for SkeletonParams {
    fn default() -> Self {
        SkeletonParams {
            radius: [0.5, 4.0],
            vertical_angle: 60.0,
            epikarst_depth: 15.0,
            keyhole_height: 10.0,
        }
    }
}

impl SkeletonParams {
    pub(crate) fn check(&self, c: &mut Checks) {
        let [lo, hi] = self.radius;
        c.positive("skeleton.radius", lo);
        if lo.is_finite() && hi.is_finite() && hi < lo {
            c.report("skeleton.radius", format!("[{lo}, {hi}] is not a range (max < min)"));
        }
        if c.finite("skeleton.vertical_angle", &[self.vertical_angle])
            && !(self.vertical_angle > 0.0 && self.vertical_angle <= 90.0)
        {
            c.report(
                "skeleton.vertical_angle",
                format!("must be in (0, 90] degrees, got {}", self.vertical_angle),
            );
        }
        c.non_negative("skeleton.epikarst_depth", self.epikarst_depth);
        c.non_negative("skeleton.keyhole_height", self.keyhole_height);
    }
}
