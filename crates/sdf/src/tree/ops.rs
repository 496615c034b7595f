//! Operators of the construction tree (Paris et al. 2021 §6, after [WGG99]), each keeping the
//! 1-Lipschitz bound of its operands:
//!
//! - union min, intersection max, difference max(a, −b) (written inline where they are used):
//!   Lipschitz constants do not grow;
//! - smooth union: the quadratic smooth minimum min(a, b) − h²k/4 with h = max(k − |a − b|, 0)/k.
//!   Its partial derivatives are (1 − t, t) with t ∈ [0, 1], so its gradient is a convex
//!   combination of the operands' gradients: still 1-Lipschitz. It deepens the union by at
//!   most k/4, which is what the BVH must allow for when it prunes.
//! - warp: f(p + A·w(p)) with a displacement field w of Jacobian norm ≤ L has Lipschitz constant
//!   ≤ 1 + A·L; dividing by that factor compensates it;
//! - detail: f(p) + A·n(p) for a noise n of gradient ≤ G, divided by 1 + A·G;
//! - the clamp of the karst unions (caves and surface water) at [`REACH`]: a min, it keeps the
//!   bound.

use glam::DVec3;

/// The karst terms are clamped to at most this many metres: min(cave, REACH) keeps the sign and
/// the Lipschitz bound (a smaller |f| is still a distance bound), and spares eval every leaf
/// farther away: a point deep in rock visits only the leaves within REACH.
pub const REACH: f64 = 8.0;

/// Quadratic smooth minimum of radius k ≥ 0 (the plain minimum for k = 0).
pub fn smooth_union(a: f64, b: f64, k: f64) -> f64 {
    if k <= 0.0 {
        return a.min(b);
    }
    let h = (k - (a - b).abs()).max(0.0) / k;
    a.min(b) - h * h * k * 0.25
}

/// The warped field f(p + amplitude·w(p)) / (1 + amplitude·jacobian_bound).
pub fn warp(
    f: impl Fn(DVec3) -> f64,
    w: impl Fn(DVec3) -> DVec3,
    amplitude: f64,
    jacobian_bound: f64,
    p: DVec3,
) -> f64 {
    f(p + w(p) * amplitude) / (1.0 + amplitude * jacobian_bound)
}

/// Detail noise added to a field value: (f + amplitude·n) / (1 + amplitude·gradient_bound).
pub fn detail(f: f64, noise: f64, amplitude: f64, gradient_bound: f64) -> f64 {
    (f + amplitude * noise) / (1.0 + amplitude * gradient_bound)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::testing::{Pairs, assert_lipschitz};
    use crate::tree::noise::WaveNoise;
    use karst_scene::rng::Random;

    fn ball(c: DVec3, r: f64) -> impl Fn(DVec3) -> f64 {
        move |p| p.distance(c) - r
    }

    #[test]
    fn operators_are_one_lipschitz() {
        let a = ball(DVec3::ZERO, 3.0);
        let b = ball(DVec3::new(2.5, 0.5, 0.0), 2.0);
        let pairs = || Pairs::new(5, 8.0, 3.0);
        assert_lipschitz(|p| a(p).min(b(p)), pairs(), 5000);
        assert_lipschitz(|p| a(p).max(b(p)), pairs(), 5000);
        assert_lipschitz(|p| a(p).max(-b(p)), pairs(), 5000);
        assert_lipschitz(|p| smooth_union(a(p), b(p), 1.5), pairs(), 5000);
        assert_lipschitz(|p| -smooth_union(-a(p), b(p), 1.5), pairs(), 5000);
        let noise = WaveNoise::draw(&mut Random::stream(1, "sdf", "test"), 2.0);
        let g = noise.gradient_bound();
        assert_lipschitz(|p| detail(a(p), noise.value(p), 0.4, g), pairs(), 5000);
        let jacobian = g * 3f64.sqrt();
        assert_lipschitz(|p| warp(&a, |q| noise.vector(q), 0.5, jacobian, p), pairs(), 5000);
    }

    #[test]
    fn smooth_union_stays_within_k_over_4() {
        for (x, y) in [(0.0, 0.0), (0.3, -0.2), (2.0, 1.0)] {
            let s = smooth_union(x, y, 1.0);
            assert!(s <= x.min(y) && s >= x.min(y) - 0.25);
        }
        assert_eq!(smooth_union(0.0, 2.0, 1.0), 0.0);
    }
}
