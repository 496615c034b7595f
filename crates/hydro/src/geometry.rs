//! Water geometry of a segment (Emilien et al. 2015 §5.2.2, adapted to conduits).
//!
//! Speed grows linearly with slope, δ = k·s (k = `hydro.speed_factor`, the paper's k = 10),
//! with s at least `hydro.min_slope` so that flat conduits still drain. Where the paper gives
//! the water a triangular bed, γ = δ·ε·ζ/2, a conduit gives it a circular one: the wetted
//! area A = Q/δ (Q the discharge in m³/s) is the circular segment of the conduit's radius
//! whose depth ζ is solved for, and the free surface's width ε is the chord at that depth.
//! A conduit too small for its flow runs full (pressure flow: depth 2r, no free surface).
//!
//! In a shaft the water falls freely: it leaves the lip with the horizontal speed it had
//! (kept from the last contact segment upstream) and follows a parabola under gravity; the
//! jet's cross-section is A = Q/v at mid-height, drawn as a round jet no wider than the shaft.

use std::f64::consts::PI;

use glam::{DVec2, DVec3};

use crate::payload::Fall;

/// Gravity, m/s².
pub const G: f64 = 9.81;

/// Depth and width of a free surface.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FreeSurface {
    pub depth: f64,
    pub width: f64,
}

/// Area of the circular segment of depth `d` in a circle of radius `r`.
fn segment_area(r: f64, d: f64) -> f64 {
    let h = r - d;
    r * r * (h / r).clamp(-1.0, 1.0).acos() - h * (d * (2.0 * r - d)).max(0.0).sqrt()
}

/// The free surface of `area` m² of water in a conduit of radius `r`.
pub fn free_surface(area: f64, r: f64) -> FreeSurface {
    if area <= 0.0 {
        return FreeSurface { depth: 0.0, width: 0.0 };
    }
    if area >= PI * r * r {
        return FreeSurface { depth: 2.0 * r, width: 0.0 };
    }
    let (mut lo, mut hi) = (0.0, 2.0 * r);
    for _ in 0..60 {
        let mid = 0.5 * (lo + hi);
        if segment_area(r, mid) < area { lo = mid } else { hi = mid }
    }
    let depth = 0.5 * (lo + hi);
    FreeSurface { depth, width: 2.0 * (depth * (2.0 * r - depth)).sqrt() }
}

/// Speed of water running down `slope` radians.
pub fn speed(slope: f64, factor: f64, min_slope: f64) -> f64 {
    factor * slope.max(min_slope)
}

/// The free fall of `discharge` m³/s from `lip` down to `bottom`'s elevation, leaving the
/// lip at horizontal speed `v0` along `direction`, in a shaft of radius `r`; with the jet's
/// size as a surface (depth = width = jet diameter).
pub fn fall(
    lip: DVec3,
    bottom: DVec3,
    direction: DVec2,
    v0: f64,
    discharge: f64,
    r: f64,
) -> (Fall, FreeSurface) {
    let drop = (lip.z - bottom.z).max(0.0);
    let throw = v0 * (2.0 * drop / G).sqrt();
    let impact = DVec3::new(lip.x + direction.x * throw, lip.y + direction.y * throw, lip.z - drop);
    let v_mid = (v0 * v0 + G * drop).sqrt().max(f64::MIN_POSITIVE);
    let jet = (2.0 * (discharge / v_mid / PI).sqrt()).min(2.0 * r);
    let fall = Fall {
        lip: lip.to_array(),
        direction: direction.to_array(),
        speed: v0,
        drop,
        throw,
        impact: impact.to_array(),
    };
    (fall, FreeSurface { depth: jet, width: jet })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn half_a_conduit_of_water_is_at_mid_height() {
        let s = free_surface(PI * 4.0 / 2.0, 2.0);
        assert!((s.depth - 2.0).abs() < 1e-9 && (s.width - 4.0).abs() < 1e-9, "{s:?}");
        assert_eq!(free_surface(100.0, 1.0), FreeSurface { depth: 2.0, width: 0.0 });
        assert!(free_surface(0.01, 1.0).depth < free_surface(0.1, 1.0).depth);
    }

    #[test]
    fn a_fall_follows_the_parabola_of_its_lip_speed() {
        let (f, jet) = fall(DVec3::new(0.0, 0.0, 20.0), DVec3::ZERO, DVec2::X, 2.0, 0.5, 3.0);
        // t = √(2·20/g), throw = v0·t.
        assert!((f.throw - 2.0 * (40.0 / G).sqrt()).abs() < 1e-12);
        assert_eq!(f.impact[2], 0.0);
        assert!((f.impact[0] - f.throw).abs() < 1e-12);
        assert!(jet.width > 0.0 && jet.width < 6.0);
    }
}
