//! Fracture families: sets of parallel fractures, given by the azimuth of their traces (strike),
//! an optional dip, an angular tolerance and a weight. Conduits tend to follow fracture planes
//! (Paris et al. 2021 §4.2; KarstNSim §1.3, fractures as azimuth ± tolerance).

use serde::{Deserialize, Serialize};

use crate::Point;

/// One fracture family (`[[geology.fractures]]`).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct FractureFamily {
    /// Unique name of the family.
    pub name: String,
    /// Azimuth of the fracture traces (strike), degrees clockwise from north: N030 is 30.
    pub azimuth: f64,
    /// Dip of the fracture planes in degrees (towards azimuth + 90°); default 90, vertical.
    #[serde(default = "vertical")]
    pub dip: f64,
    /// Angular tolerance, degrees; default 10.
    #[serde(default = "ten")]
    pub tolerance: f64,
    /// Relative weight of the family; default 1.
    #[serde(default = "one")]
    pub weight: f64,
}

fn vertical() -> f64 {
    90.0
}

fn ten() -> f64 {
    10.0
}

fn one() -> f64 {
    1.0
}

impl FractureFamily {
    /// Unit normal of the fracture planes.
    pub fn normal(&self) -> Point {
        let (sin_dip, cos_dip) = self.dip.to_radians().sin_cos();
        let (sin_az, cos_az) = self.azimuth.to_radians().sin_cos();
        Point::new(sin_dip * cos_az, -sin_dip * sin_az, cos_dip)
    }

    /// Unit direction of the traces (horizontal, along the azimuth).
    pub fn strike(&self) -> Point {
        let (sin_az, cos_az) = self.azimuth.to_radians().sin_cos();
        Point::new(sin_az, cos_az, 0.0)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn normal_is_perpendicular_to_the_strike() {
        for (azimuth, dip) in [(0.0, 90.0), (30.0, 90.0), (150.0, 60.0), (275.0, 10.0)] {
            let f = FractureFamily { name: "f".into(), azimuth, dip, tolerance: 5.0, weight: 1.0 };
            assert!(f.normal().dot(f.strike()).abs() < 1e-12);
            assert!((f.normal().length() - 1.0).abs() < 1e-12);
        }
        let n030 = FractureFamily { name: "f".into(), azimuth: 30.0, dip: 90.0, tolerance: 5.0, weight: 1.0 };
        assert!(n030.normal().z.abs() < 1e-12);
    }
}
