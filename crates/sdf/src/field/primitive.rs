//! The leaves of the karst volume, ready to evaluate, with their detail noise and their boxes.
//!
//! Every leaf i contributes v_i(p) = max(detail(f_i(p)), box_i(p)) (spheres: see
//! [`sphere_value`]), where f_i is the leaf's 1-Lipschitz bound, detail adds the per-type fBm
//! of amplitude A_i with its gradient compensated (see [`crate::tree::ops::detail`]), and box_i is
//! the distance to the leaf's box grown by A_i (signed: negative inside). The max keeps the
//! bound and changes nothing inside the box (there the box's value is at most minus the
//! distance to the leaf's surface), but guarantees v_i ≥ distance to the box, which makes the
//! BVH's pruning exact: skipping a node whose box is farther than the current minimum never
//! changes the union.
//!
//! Leaves are small: a sphere is four f32, a sweep a [`SweepLeaf`] (12 bytes) whose two nodes
//! and unit polygons live in the shared [`SweepTable`]; its frame and sections are rebuilt when
//! it is evaluated. The conduit type (hence the detail amplitude) is one byte beside each.

use std::cell::Cell;

use glam::DVec3;
use karst_skeleton::ConduitType;

use crate::Capsule;
use crate::detail::walls::Relief;
use crate::tree::chamber::Chamber;
use crate::tree::noise::WaveNoise;
use crate::tree::ops;
use crate::tree::sweep::{SweepLeaf, SweepTable, to_dvec};

/// A leaf before it is placed in the BVH.
#[derive(Debug, Clone)]
pub enum Leaf {
    /// (x, y, z, radius) and the conduit type.
    Sphere([f32; 4], ConduitType),
    Sweep(SweepLeaf, ConduitType),
    /// The water of a segment: its sweep below a level.
    Water(WaterLeaf),
    Chamber(Chamber),
    Capsule(Capsule),
}

/// The water of a segment: its sweep below `level` (height above the axis; +∞ flooded).
#[derive(Debug, Clone, Copy)]
pub struct WaterLeaf {
    pub sweep: SweepLeaf,
    pub level: f32,
}

/// Leaf kinds, as the BVH's leaf nodes record them.
pub const SPHERE: u8 = 0;
pub const SWEEP: u8 = 1;
pub const WATER: u8 = 2;
pub const CHAMBER: u8 = 3;
pub const CAPSULE: u8 = 4;

impl Leaf {
    /// The leaf's kind: a BVH leaf node holds leaves of one kind.
    pub fn kind(&self) -> u8 {
        match self {
            Leaf::Sphere(..) => SPHERE,
            Leaf::Sweep(..) => SWEEP,
            Leaf::Water(_) => WATER,
            Leaf::Chamber(_) => CHAMBER,
            Leaf::Capsule(_) => CAPSULE,
        }
    }

    /// Detail amplitudes, metres: spheres and sweeps by their conduit type and size, others
    /// none.
    pub fn amplitude(&self, ctx: &Context) -> Amp {
        match self {
            Leaf::Sphere(s, t) => ctx.amp(*t as u8, s[3]),
            Leaf::Sweep(s, t) => ctx.amp(*t as u8, s.extent),
            _ => Amp::NONE,
        }
    }

    /// Axis-aligned box containing the detailed leaf.
    pub fn bounds(&self, ctx: &Context) -> (DVec3, DVec3) {
        let a = self.amplitude(ctx).total();
        let (lo, hi) = match self {
            Leaf::Sphere(s, _) => sphere_bounds(s),
            Leaf::Sweep(s, _) => ctx.sweeps.bounds(s),
            Leaf::Water(w) => ctx.sweeps.bounds(&w.sweep),
            Leaf::Chamber(c) => c.bounds(),
            Leaf::Capsule(c) => c.bounds(),
        };
        (lo - DVec3::splat(a), hi + DVec3::splat(a))
    }
}

fn sphere_bounds(s: &[f32; 4]) -> (DVec3, DVec3) {
    let c = to_dvec([s[0], s[1], s[2]]);
    (c - DVec3::splat(s[3] as f64), c + DVec3::splat(s[3] as f64))
}

/// A leaf's two noise amplitudes, metres: the per-type detail and the rough-wall relief
/// (`passage_detail = "full"`, relative to the leaf's size; 0 otherwise).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Amp {
    pub detail: f64,
    pub relief: f64,
}

impl Amp {
    pub const NONE: Amp = Amp { detail: 0.0, relief: 0.0 };

    /// The largest displacement of the wall: the sum of both amplitudes.
    pub fn total(self) -> f64 {
        self.detail + self.relief
    }
}

/// What leaves share during the evaluation of one point: the noises, the sweep table, the
/// amplitudes, and the detail noises at that point, computed at most once (a context serves one
/// point only).
pub struct Context<'a> {
    pub detail: &'a WaveNoise,
    pub detail_gradient: f64,
    pub chamber: &'a WaveNoise,
    pub bias: f64,
    pub sweeps: &'a SweepTable,
    /// Detail amplitude of each conduit type (index: the type's discriminant).
    pub amplitude: &'a [f64; 8],
    noise_at: Cell<Option<f64>>,
    /// The rough-wall relief and its gradient bound, with `full` passage detail.
    relief: Option<(&'a Relief, f64)>,
    relief_at: Cell<Option<f64>>,
}

impl<'a> Context<'a> {
    /// A context for one point; `detail_gradient` is `detail.gradient_bound()`, computed once
    /// per field rather than per point.
    pub fn new(
        detail: &'a WaveNoise,
        detail_gradient: f64,
        chamber: &'a WaveNoise,
        bias: f64,
        sweeps: &'a SweepTable,
        amplitude: &'a [f64; 8],
    ) -> Self {
        Context {
            detail,
            detail_gradient,
            chamber,
            bias,
            sweeps,
            amplitude,
            noise_at: Cell::new(None),
            relief: None,
            relief_at: Cell::new(None),
        }
    }

    /// The context with rough-wall relief; `gradient` is `relief.gradient_bound()`.
    pub fn with_relief(mut self, relief: Option<&'a Relief>, gradient: f64) -> Self {
        self.relief = relief.map(|r| (r, gradient));
        self
    }

    /// The amplitudes of a leaf of conduit type `kind` (its discriminant) and size `size`
    /// (a sphere's radius, a sweep's extent), metres.
    pub fn amp(&self, kind: u8, size: f32) -> Amp {
        let relief = self.relief.map_or(0.0, |(r, _)| r.amplitude(size as f64));
        Amp { detail: self.amplitude[kind as usize], relief }
    }

    fn relief_noise(&self, relief: &Relief, p: DVec3) -> f64 {
        if let Some(n) = self.relief_at.get() {
            return n;
        }
        let n = relief.noise.value(p);
        self.relief_at.set(Some(n));
        n
    }

    fn noise(&self, p: DVec3) -> f64 {
        if let Some(n) = self.noise_at.get() {
            return n;
        }
        let n = self.detail.value(p);
        self.noise_at.set(Some(n));
        n
    }

    /// detail(f): f + A·n + R·r with both noises bounded by their gradients. Without relief
    /// it is exactly crate::tree::ops::detail. With relief, the quotient g = (f + A·n + R·r)/(1 + L)
    /// (L = A·G + R·G_r) clamped to the shell [f − M, f + M] around f (M = A + R): where
    /// f + A·n + R·r ≤ 0, f − M ≤ it and g ≤ 0, and where it is ≥ 0, f + M ≥ it and g ≥ 0,
    /// so the clamp keeps the sign and the surface; a clamp of three 1-Lipschitz functions is
    /// 1-Lipschitz. Far from the wall the value is f ∓ M, not f/(1 + L), which lets the mesher
    /// and the BVH prove most of the space empty or full; beyond |f| ≥ M(2 + L)/L the clamp
    /// settles the value and the noises are not evaluated (docs/sdf.md, "Rough walls").
    fn detail(&self, f: f64, p: DVec3, a: Amp) -> f64 {
        if let (Some((relief, gradient)), true) = (self.relief, a.relief > 0.0) {
            let (m, lipschitz) = (a.total(), a.detail * self.detail_gradient + a.relief * gradient);
            if f.abs() * lipschitz >= m * (2.0 + lipschitz) {
                return f - m.copysign(f);
            }
            let n = if a.detail > 0.0 { a.detail * self.noise(p) } else { 0.0 };
            let r = a.relief * self.relief_noise(relief, p);
            return ((f + n + r) / (1.0 + lipschitz)).clamp(f - m, f + m);
        }
        let amplitude = a.detail;
        if amplitude > 0.0 { ops::detail(f, self.noise(p), amplitude, self.detail_gradient) } else { f }
    }

    /// The smallest value detail(f) can take for any noise (both at −1); detail is
    /// nondecreasing in f, so this of a lower bound of f is a lower bound of detail(f).
    fn detail_floor(&self, f: f64, a: Amp) -> f64 {
        if let (Some((_, gradient)), true) = (self.relief, a.relief > 0.0) {
            let (m, lipschitz) = (a.total(), a.detail * self.detail_gradient + a.relief * gradient);
            return ((f - m) / (1.0 + lipschitz)).clamp(f - m, f + m);
        }
        let amplitude = a.detail;
        if amplitude > 0.0 { (f - amplitude) / (1.0 + amplitude * self.detail_gradient) } else { f }
    }
}

/// A sphere's value, clamped by the sphere grown by its amplitude A rather than by its box:
/// the grown sphere's distance f − A is at least its box's signed distance (so the BVH's
/// pruning stays exact), and inside it (f ≤ A) detail(f) ≥ f − A, so the clamp changes nothing.
/// Any value ≥ `limit` when v(p) ≥ `limit`.
pub fn sphere_value(p: DVec3, s: &[f32; 4], amp: Amp, limit: f64, ctx: &Context) -> f64 {
    let f = p.distance(to_dvec([s[0], s[1], s[2]])) - s[3] as f64;
    let a = amp.total();
    if f - a >= limit {
        return f - a;
    }
    ctx.detail(f, p, amp).max(f - a)
}

/// A sweep's value, or any value ≥ `limit` when it is ≥ `limit`: the box, then the sweep's
/// lower bound with the smallest detail, before the section's distance.
pub fn sweep_value(p: DVec3, leaf: &SweepLeaf, amp: Amp, limit: f64, ctx: &Context) -> f64 {
    let a = amp.total();
    let (lo, hi) = ctx.sweeps.bounds(leaf);
    let outside = signed_box_distance(lo - DVec3::splat(a), hi + DVec3::splat(a), p);
    if outside >= limit {
        return outside;
    }
    let sweep = ctx.sweeps.sweep(leaf);
    let (l, q) = sweep.local(p);
    let bound = ctx.detail_floor(sweep.lower_bound_local(l, q), amp);
    if bound >= limit {
        return bound.max(outside);
    }
    ctx.detail(sweep.distance_local(l, q), p, amp).max(outside)
}

/// A cheap lower bound of [`sweep_value`]: the larger of the box's signed distance and the
/// detailed capsule bound (distance to the axis segment minus the extent, times the factor).
pub fn sweep_floor(p: DVec3, leaf: &SweepLeaf, amp: Amp, ctx: &Context) -> f64 {
    let a = amp.total();
    let (s0, s1) = ctx.sweeps.ends(leaf);
    let r = leaf.extent as f64;
    let outside = signed_box_distance(s0.min(s1) - DVec3::splat(r + a), s0.max(s1) + DVec3::splat(r + a), p);
    let ab = s1 - s0;
    let t = ((p - s0).dot(ab) / ab.length_squared()).clamp(0.0, 1.0);
    let capsule = (p - s0 - ab * t).length() - r;
    ctx.detail_floor(capsule * leaf.scale as f64, amp).max(outside)
}

/// A water piece's value: its sweep below its level.
pub fn water_value(p: DVec3, w: &WaterLeaf, limit: f64, ctx: &Context) -> f64 {
    let (lo, hi) = ctx.sweeps.bounds(&w.sweep);
    let outside = signed_box_distance(lo, hi, p);
    if outside >= limit {
        return outside;
    }
    let sweep = ctx.sweeps.sweep(&w.sweep);
    let (l, q) = sweep.local(p);
    let surface = sweep.height(p) - w.level as f64;
    let bound = sweep.lower_bound_local(l, q).max(surface);
    if bound >= limit {
        return bound.max(outside);
    }
    sweep.distance_local(l, q).max(surface).max(outside)
}

/// A chamber's value.
pub fn chamber_value(p: DVec3, c: &Chamber, limit: f64, ctx: &Context) -> f64 {
    let (lo, hi) = c.bounds();
    let outside = signed_box_distance(lo, hi, p);
    if outside >= limit {
        return outside;
    }
    c.distance(p, ctx.chamber, ctx.bias).max(outside)
}

/// A capsule's value.
pub fn capsule_value(p: DVec3, c: &Capsule) -> f64 {
    let (lo, hi) = c.bounds();
    c.distance(p).max(signed_box_distance(lo, hi, p))
}

/// Signed distance to the box: negative inside, at most minus the distance to the surface of
/// anything inside the box, so max(v, box) = v there.
pub fn signed_box_distance(lo: DVec3, hi: DVec3, p: DVec3) -> f64 {
    let d = (lo - p).max(p - hi);
    d.max(DVec3::ZERO).length() + d.max_element().min(0.0)
}
