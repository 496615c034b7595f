//! The domain: the axis-aligned box of rock karstgen models.

use serde::{Deserialize, Serialize};

use crate::Point;

/// An axis-aligned box, `min` to `max`, metres.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Domain {
    /// South-west-bottom corner `[x, y, z]`.
    pub min: [f64; 3],
    /// North-east-top corner `[x, y, z]`.
    pub max: [f64; 3],
}

impl Domain {
    #[inline]
    pub fn min(&self) -> Point {
        Point::from_array(self.min)
    }

    #[inline]
    pub fn max(&self) -> Point {
        Point::from_array(self.max)
    }

    pub fn size(&self) -> Point {
        self.max() - self.min()
    }

    pub fn centre(&self) -> Point {
        (self.min() + self.max()) * 0.5
    }

    /// True when `p` is inside the box or on its boundary.
    #[inline]
    pub fn contains(&self, p: Point) -> bool {
        p.cmpge(self.min()).all() && p.cmple(self.max()).all()
    }

    /// Signed distance to the box: negative inside. Exact (1-Lipschitz).
    pub fn signed_distance(&self, p: Point) -> f64 {
        let c = self.centre();
        let h = self.size() * 0.5;
        let q = (p - c).abs() - h;
        q.max(Point::ZERO).length() + q.max_element().min(0.0)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn signed_distance_of_the_box() {
        let d = Domain { min: [0.0, 0.0, 0.0], max: [10.0, 10.0, 4.0] };
        assert_eq!(d.signed_distance(Point::new(5.0, 5.0, 2.0)), -2.0);
        assert_eq!(d.signed_distance(Point::new(13.0, 5.0, 2.0)), 3.0);
        assert!((d.signed_distance(Point::new(13.0, 14.0, 2.0)) - 5.0).abs() < 1e-12);
        assert!(d.contains(Point::new(10.0, 0.0, 4.0)));
        assert!(!d.contains(Point::new(10.0, 0.0, 4.1)));
    }
}
