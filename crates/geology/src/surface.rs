//! Geological surfaces given as z = s(x, y): water tables and inception horizons.
//!
//! A surface is a plane given by its elevation at a reference point, its dip (degrees below
//! horizontal) and its dip direction (azimuth of steepest descent, degrees clockwise from
//! north = +y). A water table with a hydraulic gradient of 4 % towards its spring is a plane
//! dipping atan(0.04) ≈ 2.29° towards the spring.

use serde::{Deserialize, Serialize};

use crate::Point;

/// A named surface z = s(x, y) (`[[geology.water_tables]]`, `[[geology.horizons]]`).
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
    /// Dip in degrees, from 0 (horizontal) to below 90; default 0.
    #[serde(default)]
    pub dip: f64,
    /// Dip direction in degrees clockwise from north; default 0.
    #[serde(default)]
    pub dip_direction: f64,
}

impl Surface {
    /// Elevation of the surface at (x, y).
    pub fn elevation_at(&self, x: f64, y: f64) -> f64 {
        let (sin, cos) = self.dip_direction.to_radians().sin_cos();
        let along = (x - self.origin[0]) * sin + (y - self.origin[1]) * cos;
        self.elevation - self.dip.to_radians().tan() * along
    }

    /// Signed vertical offset of `p` from the surface: positive above it.
    pub fn height_above(&self, p: Point) -> f64 {
        p.z - self.elevation_at(p.x, p.y)
    }

    /// Euclidean distance from `p` to the (planar) surface.
    pub fn distance(&self, p: Point) -> f64 {
        self.height_above(p).abs() * self.dip.to_radians().cos()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn plane_dips_towards_its_dip_direction() {
        let east = Surface {
            name: "h".into(),
            elevation: 100.0,
            origin: [0.0, 0.0],
            dip: 45.0,
            dip_direction: 90.0,
        };
        assert!((east.elevation_at(10.0, 0.0) - 90.0).abs() < 1e-9);
        assert!((east.elevation_at(0.0, 10.0) - 100.0).abs() < 1e-9);
        let d = east.distance(Point::new(0.0, 0.0, 110.0));
        assert!((d - 10.0 * std::f64::consts::FRAC_1_SQRT_2).abs() < 1e-9);
    }
}
