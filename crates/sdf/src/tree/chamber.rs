//! The chamber leaf: a foundation shape perturbed by gradient noise through Perlin's bias
//! function (Cui et al. 2011 §3.1), kept 1-Lipschitz.
//!
//! Cui et al. call a voxel air when a noise value in [0, 1] is below the biased foundation
//! value bias_b(t) = t^(ln b / ln 0.5), where t is 1 deep inside the foundation and 0 at its
//! wall; small b hugs the foundation, larger b gives rough walls. Here the foundation is a
//! capsule warped by a bounded displacement (so breakdown chambers are not perfect pills), t is
//! its depth in units of D (the depth the axis keeps under the warp), and the chamber is the zero set of
//!   g(p) = n01(p) − bias_b(t(p)),
//! whose gradient is at most G/2 + e/D (G the noise gradient bound, e = ln b / ln 0.5 ≥ 1 the
//! bias exponent, so bias′ ≤ e). Dividing by that bound makes g 1-Lipschitz; taking the max with
//! the foundation's own distance keeps the leaf positive and growing outside the foundation
//! (no floating islands beyond it, and the BVH may prune by the foundation's box).

use glam::DVec3;
use serde::{Deserialize, Serialize};

use crate::tree::noise::WaveNoise;
use crate::tree::ops;
use crate::tree::sweep::to_dvec;

/// A chamber as the artifact stores it.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct ChamberSpec {
    pub a: [f32; 3],
    pub b: [f32; 3],
    pub radius: f32,
}

/// A chamber ready to evaluate.
#[derive(Debug, Clone)]
pub struct Chamber {
    a: DVec3,
    b: DVec3,
    radius: f64,
    /// Warp amplitude, metres.
    warp: f64,
}

/// Warp amplitude in foundation radii.
const WARP: f64 = 0.1;

impl Chamber {
    pub fn new(spec: &ChamberSpec) -> Self {
        let radius = spec.radius as f64;
        Chamber { a: to_dvec(spec.a), b: to_dvec(spec.b), radius, warp: WARP * radius }
    }

    fn capsule(&self, p: DVec3) -> f64 {
        let ab = self.b - self.a;
        let t = if ab.length_squared() > 0.0 {
            ((p - self.a).dot(ab) / ab.length_squared()).clamp(0.0, 1.0)
        } else {
            0.0
        };
        (p - self.a - ab * t).length() - self.radius
    }

    /// The warped foundation (1-Lipschitz).
    fn foundation(&self, p: DVec3, noise: &WaveNoise) -> f64 {
        let jacobian = noise.gradient_bound() * 3f64.sqrt();
        ops::warp(|q| self.capsule(q), |q| noise.vector(q), self.warp, jacobian, p)
    }

    /// The 1-Lipschitz leaf, negative in the chamber; `bias` in (0, 0.5].
    pub fn distance(&self, p: DVec3, noise: &WaveNoise, bias: f64) -> f64 {
        let foundation = self.foundation(p, noise);
        if foundation >= 0.0 {
            return foundation;
        }
        let exponent = bias.ln() / 0.5f64.ln();
        // Depth at which t reaches 1: the axis stays at least this deep under the warp.
        let jacobian = noise.gradient_bound() * 3f64.sqrt();
        let depth = (self.radius - self.warp * 3f64.sqrt()) / (1.0 + self.warp * jacobian);
        let t = (-foundation / depth).min(1.0);
        let g = 0.5 * (noise.value(p) + 1.0) - t.powf(exponent);
        let lipschitz = 0.5 * noise.gradient_bound() + exponent / depth;
        (g / lipschitz).max(foundation)
    }

    /// Bounds of the warped foundation.
    pub fn bounds(&self) -> (DVec3, DVec3) {
        let r = DVec3::splat(self.radius + self.warp * 3f64.sqrt());
        (self.a.min(self.b) - r, self.a.max(self.b) + r)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::testing::{Pairs, assert_lipschitz};
    use karst_scene::rng::Random;

    #[test]
    fn chambers_are_one_lipschitz_and_hollow() {
        let noise = WaveNoise::draw(&mut Random::stream(4, "sdf", "chamber"), 6.0);
        let c = Chamber::new(&ChamberSpec { a: [0.0, 0.0, 0.0], b: [8.0, 2.0, 0.0], radius: 6.0 });
        for bias in [0.05, 0.2, 0.5] {
            assert_lipschitz(|p| c.distance(p, &noise, bias), Pairs::new(8, 14.0, 3.0), 20_000);
            assert!(c.distance(DVec3::new(4.0, 1.0, 0.0), &noise, bias) < 0.0, "air at the centre");
            assert!(c.distance(DVec3::new(4.0, 1.0, 9.0), &noise, bias) > 0.0, "rock beyond the wall");
        }
    }
}
