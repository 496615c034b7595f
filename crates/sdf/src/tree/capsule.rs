//! The capsule: all points within `radius` of a segment. Its exact signed distance is
//! |p − closest point of ab| − r.

use glam::DVec3;
use serde::{Deserialize, Serialize};

use karst_artifact::Invalid;
use karst_artifact::check::{self, MAX_COORDINATE};

/// A capsule around the segment a–b.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Capsule {
    pub a: [f64; 3],
    pub b: [f64; 3],
    pub radius: f64,
}

impl Capsule {
    /// Finite ends and a finite positive radius; `at` names the capsule in errors.
    pub(crate) fn validate(&self, at: &dyn Fn() -> String) -> Result<(), Invalid> {
        check::position(|| format!("{}.a", at()), &self.a)?;
        check::position(|| format!("{}.b", at()), &self.b)?;
        check::positive(|| format!("{}.radius", at()), self.radius, MAX_COORDINATE)
    }

    /// Exact signed distance: negative inside.
    pub fn distance(&self, p: DVec3) -> f64 {
        let a = DVec3::from_array(self.a);
        let ab = DVec3::from_array(self.b) - a;
        let ap = p - a;
        let len2 = ab.length_squared();
        let t = if len2 > 0.0 { (ap.dot(ab) / len2).clamp(0.0, 1.0) } else { 0.0 };
        (ap - ab * t).length() - self.radius
    }

    /// Axis-aligned bounds `(lo, hi)`.
    pub fn bounds(&self) -> (DVec3, DVec3) {
        let (a, b) = (DVec3::from_array(self.a), DVec3::from_array(self.b));
        (a.min(b) - DVec3::splat(self.radius), a.max(b) + DVec3::splat(self.radius))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn distance_to_a_capsule() {
        let c = Capsule { a: [0.0, 0.0, 0.0], b: [10.0, 0.0, 0.0], radius: 2.0 };
        assert_eq!(c.distance(DVec3::new(5.0, 0.0, 0.0)), -2.0);
        assert_eq!(c.distance(DVec3::new(5.0, 3.0, 4.0)), 3.0);
        assert_eq!(c.distance(DVec3::new(-3.0, 0.0, 0.0)), 1.0);
    }
}
