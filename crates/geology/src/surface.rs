//! Geological surfaces: water tables, inception horizons and faults.
//!
//! A surface is a plane given by its elevation at a reference point, its dip (degrees below
//! horizontal) and its dip direction (azimuth of steepest descent, degrees clockwise from
//! north = +y). A water table with a hydraulic gradient of 4 % towards its spring is a plane
//! dipping atan(0.04) ≈ 2.29° towards the spring. Water tables and horizons are graphs
//! z = s(x, y) (dip below 90°); faults may be vertical.

use serde::{Deserialize, Serialize};

use crate::Point;

/// A named plane (`[[geology.water_tables]]`, `[[geology.horizons]]`, `[[geology.faults]]`).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Surface {
    /// Unique name among surfaces of its kind; springs name their water table.
    pub name: String,
    /// Elevation at `origin`, metres.
    pub elevation: f64,
    /// Reference point `[x, y]`; default `[0, 0]`.
    #[serde(default)]
    pub origin: [f64; 2],
    /// Dip in degrees, from 0 (horizontal) to 90 (vertical, faults only); default 0.
    #[serde(default)]
    pub dip: f64,
    /// Dip direction in degrees clockwise from north; default 0.
    #[serde(default)]
    pub dip_direction: f64,
}

impl Surface {
    /// Upward unit normal (horizontal for a vertical plane, pointing to the dip direction).
    pub fn normal(&self) -> Point {
        let (sin_dip, cos_dip) = self.dip.to_radians().sin_cos();
        let (sin_dir, cos_dir) = self.dip_direction.to_radians().sin_cos();
        Point::new(sin_dip * sin_dir, sin_dip * cos_dir, cos_dip)
    }

    /// Signed distance from the plane, positive on the side of the upward normal.
    pub fn signed_distance(&self, p: Point) -> f64 {
        let origin = Point::new(self.origin[0], self.origin[1], self.elevation);
        self.normal().dot(p - origin)
    }

    /// Euclidean distance from `p` to the plane.
    pub fn distance(&self, p: Point) -> f64 {
        self.signed_distance(p).abs()
    }

    /// Elevation of the surface at (x, y) (not for vertical planes).
    pub fn elevation_at(&self, x: f64, y: f64) -> f64 {
        let (sin, cos) = self.dip_direction.to_radians().sin_cos();
        let along = (x - self.origin[0]) * sin + (y - self.origin[1]) * cos;
        self.elevation - self.dip.to_radians().tan() * along
    }

    /// Signed vertical offset of `p` from the surface: positive above it (not for vertical
    /// planes).
    pub fn height_above(&self, p: Point) -> f64 {
        p.z - self.elevation_at(p.x, p.y)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn plane(dip: f64, dip_direction: f64) -> Surface {
        Surface { name: "s".into(), elevation: 100.0, origin: [0.0, 0.0], dip, dip_direction }
    }

    #[test]
    fn plane_dips_towards_its_dip_direction() {
        let east = plane(45.0, 90.0);
        assert!((east.elevation_at(10.0, 0.0) - 90.0).abs() < 1e-9);
        assert!((east.elevation_at(0.0, 10.0) - 100.0).abs() < 1e-9);
        let d = east.distance(Point::new(0.0, 0.0, 110.0));
        assert!((d - 10.0 * std::f64::consts::FRAC_1_SQRT_2).abs() < 1e-9);
        assert!(east.signed_distance(Point::new(0.0, 0.0, 110.0)) > 0.0);
        assert!((east.height_above(Point::new(10.0, 0.0, 95.0)) - 5.0).abs() < 1e-9);
    }

    #[test]
    fn vertical_fault_distance_is_horizontal() {
        let fault = plane(90.0, 0.0);
        assert!((fault.distance(Point::new(3.0, -7.0, 55.0)) - 7.0).abs() < 1e-9);
    }
}
