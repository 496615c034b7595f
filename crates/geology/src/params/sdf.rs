//! `[sdf]`: the signed-distance model.

use serde::{Deserialize, Serialize};

use crate::validate::Checks;

#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct SdfParams {
    /// Factor applied to every conduit radius.
    pub radius_scale: f64,
}

impl Default for SdfParams {
    fn default() -> Self {
        SdfParams { radius_scale: 1.0 }
    }
}

impl SdfParams {
    pub(crate) fn check(&self, c: &mut Checks) {
        c.positive("sdf.radius_scale", self.radius_scale);
    }
}
