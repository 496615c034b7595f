//! The leaves of the karst volume, ready to evaluate, with their detail noise and their boxes.
//!
//! Every leaf i contributes v_i(p) = max(detail(f_i(p)), box_i(p)) (spheres: see
//! [`sphere_value`]), where f_i is the leaf's
//! 1-Lipschitz bound, detail adds the per-type fBm of amplitude A_i with its gradient
//! compensated (see [`crate::ops::detail`]), and box_i is the distance to the leaf's box grown by
//! A_i (signed: negative inside). The max keeps the bound and changes nothing inside the box
//! (there the box's value is at most minus the distance to the leaf's surface), but guarantees v_i ≥ distance to the box, which makes the BVH's pruning
//! exact: skipping a node whose box is farther than the current minimum never changes the union.

use std::cell::Cell;

use glam::DVec3;

use crate::Capsule;
use crate::chamber::Chamber;
use crate::noise::WaveNoise;
use crate::ops;
use crate::sweep::{Sweep, to_dvec};

/// A leaf of the karst volume.
#[derive(Debug, Clone)]
pub enum Primitive {
    Sphere {
        centre: [f32; 3],
        radius: f32,
        amplitude: f32,
    },
    Capsule(Box<Capsule>),
    Sweep(Box<(Sweep, f64)>),
    Chamber(Box<Chamber>),
    /// The water of a segment: its sweep below a level (height above the axis; +∞ flooded).
    Water(Box<(Sweep, f64)>),
}

/// What leaves share during the evaluation of one point: the noises, and the detail noise at
/// that point, computed at most once (a context serves one point only).
pub struct Context<'a> {
    pub detail: &'a WaveNoise,
    pub detail_gradient: f64,
    pub chamber: &'a WaveNoise,
    pub bias: f64,
    noise_at: Cell<Option<f64>>,
}

impl<'a> Context<'a> {
    pub fn new(detail: &'a WaveNoise, chamber: &'a WaveNoise, bias: f64) -> Self {
        Self::with_gradient(detail, detail.gradient_bound(), chamber, bias)
    }

    /// [`Context::new`] with the detail noise's gradient bound computed beforehand.
    pub fn with_gradient(
        detail: &'a WaveNoise,
        detail_gradient: f64,
        chamber: &'a WaveNoise,
        bias: f64,
    ) -> Self {
        Context { detail, detail_gradient, chamber, bias, noise_at: Cell::new(None) }
    }

    fn noise(&self, p: DVec3) -> f64 {
        if let Some(n) = self.noise_at.get() {
            return n;
        }
        let n = self.detail.value(p);
        self.noise_at.set(Some(n));
        n
    }

    fn detail(&self, f: f64, p: DVec3, amplitude: f64) -> f64 {
        if amplitude > 0.0 { ops::detail(f, self.noise(p), amplitude, self.detail_gradient) } else { f }
    }
}

impl Primitive {
    /// Detail amplitude, metres.
    fn amplitude(&self) -> f64 {
        match self {
            Primitive::Sphere { amplitude, .. } => *amplitude as f64,
            Primitive::Sweep(s) => s.1,
            Primitive::Capsule(_) | Primitive::Chamber(_) | Primitive::Water(_) => 0.0,
        }
    }

    /// Axis-aligned box containing the detailed leaf.
    pub fn bounds(&self) -> (DVec3, DVec3) {
        let (lo, hi) = match self {
            Primitive::Sphere { centre, radius, .. } => {
                let c = to_dvec(*centre);
                (c - DVec3::splat(*radius as f64), c + DVec3::splat(*radius as f64))
            }
            Primitive::Capsule(c) => c.bounds(),
            Primitive::Sweep(s) => s.0.bounds(),
            Primitive::Chamber(c) => c.bounds(),
            Primitive::Water(w) => w.0.bounds(),
        };
        let grow = DVec3::splat(self.amplitude());
        (lo - grow, hi + grow)
    }

    /// v(p), or any value ≥ `limit` when v(p) ≥ `limit` (the caller takes a minimum).
    pub fn value(&self, p: DVec3, limit: f64, ctx: &Context) -> f64 {
        if let Primitive::Sphere { centre, radius, amplitude } = self {
            return sphere_value(p, *centre, *radius as f64, *amplitude as f64, limit, ctx);
        }
        let (lo, hi) = self.bounds();
        let outside = signed_box_distance(lo, hi, p);
        if outside >= limit {
            return outside;
        }
        let a = self.amplitude();
        let f = match self {
            Primitive::Sweep(s) => {
                let bound = (s.0.lower_bound(p) - a) / (1.0 + a * ctx.detail_gradient);
                if bound >= limit {
                    return bound.max(outside);
                }
                s.0.distance(p)
            }
            Primitive::Chamber(c) => c.distance(p, ctx.chamber, ctx.bias),
            Primitive::Water(w) => w.0.distance(p).max(w.0.height(p) - w.1),
            Primitive::Capsule(c) => c.distance(p),
            Primitive::Sphere { centre, radius, .. } => p.distance(to_dvec(*centre)) - *radius as f64,
        };
        ctx.detail(f, p, a).max(outside)
    }
}

/// A sphere's value, clamped by the sphere grown by its amplitude A rather than by its box:
/// the grown sphere's distance f − A is at least its box's signed distance (so the BVH's
/// pruning stays exact), and inside it (f ≤ A) detail(f) ≥ f − A, so the clamp changes nothing.
fn sphere_value(p: DVec3, centre: [f32; 3], radius: f64, a: f64, limit: f64, ctx: &Context) -> f64 {
    let f = p.distance(to_dvec(centre)) - radius;
    if f - a >= limit {
        return f - a;
    }
    ctx.detail(f, p, a).max(f - a)
}

/// Signed distance to the box: negative inside, at most minus the distance to the surface of
/// anything inside the box, so max(v, box) = v there.
pub fn signed_box_distance(lo: DVec3, hi: DVec3, p: DVec3) -> f64 {
    let d = (lo - p).max(p - hi);
    d.max(DVec3::ZERO).length() + d.max_element().min(0.0)
}
