//! Conduit cross-sections: closed piecewise-quadratic curves and their signed 2D distance
//! (Paris et al. 2021 §6.2 and appendix C).
//!
//! A section is a closed uniform quadratic B-spline over `CONTROL` control points: arc i is the
//! quadratic Bézier (m_{i−1}, P_i, m_i) where m_i is the midpoint of P_i P_{i+1}, so the curve is
//! tangent-continuous and lies in the hull of its control polygon. All sections share the same
//! number of control points, so two sections interpolate by moving their control points
//! linearly, and a point of the curve moves no faster than its fastest control point.
//!
//! Coordinates: x across the conduit (to the right looking downstream), y up; the origin is the
//! conduit's axis. Signed distance: d(q, C)·δ(q, C), negative inside (appendix C). The distance
//! to an arc minimises |B(t) − q|² by solving its cubic derivative; the inside test is the
//! winding number of the curve around q, counted on a horizontal ray.

use glam::DVec2;
use serde::{Deserialize, Serialize};
use thiserror::Error;

use karst_skeleton::ConduitType;

/// Control points of every section.
pub const CONTROL: usize = 12;

/// A closed piecewise-quadratic curve.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Section {
    pub control: [DVec2; CONTROL],
}

/// The shape parameters of a section.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Shape {
    /// Half-width of the conduit, metres.
    pub radius: f32,
    /// Height over width.
    pub ratio: f32,
    /// Horizontal shift of the upper part, in half-widths (−1..1): meanders undercut one wall
    /// (canyons and keyholes only).
    pub asymmetry: f32,
}

#[derive(Debug, Clone, Copy, Error, PartialEq)]
pub enum SectionError {
    #[error("the cross-section intersects itself (arcs {0} and {1})")]
    SelfIntersecting(usize, usize),
    #[error("the cross-section has a non-positive or non-finite size")]
    Degenerate,
}

impl Section {
    /// The section of conduit type `kind` with `shape`: control polygons in units of the
    /// half-width, x across and y up, scaled by the radius; the height stretches y.
    pub fn of(kind: ConduitType, shape: Shape) -> Section {
        Section::blend([kind, kind], shape)
    }

    /// The half-and-half blend of two types' sections with one shape: the unit polygon
    /// [`unit_blend`] scaled by (radius, radius · ratio).
    pub fn blend(kinds: [ConduitType; 2], shape: Shape) -> Section {
        let unit = unit_blend(kinds, shape.asymmetry);
        let scale = scale_of(shape);
        Section { control: unit.map(|u| u * scale) }
    }

    /// Linear interpolation of the control points.
    pub fn lerp(&self, other: &Section, t: f64) -> Section {
        let mut control = self.control;
        for (c, o) in control.iter_mut().zip(&other.control) {
            *c = c.lerp(*o, t);
        }
        Section { control }
    }

    /// Largest distance of a control point to the axis: the curve lies within it.
    pub fn extent(&self) -> f64 {
        self.control.iter().map(|c| c.length()).fold(0.0, f64::max)
    }

    /// How far the section reaches along unit direction `u` from the axis, at most: the
    /// farthest control point's projection (the curve lies in their hull).
    pub fn reach(&self, u: DVec2) -> f64 {
        self.control.iter().map(|c| c.dot(u)).fold(f64::NEG_INFINITY, f64::max)
    }

    /// Lowest y of the curve (the floor): the hull's lowest control point is a lower bound,
    /// the on-curve midpoints an upper bound; arcs are evaluated at their extremum.
    pub fn floor(&self) -> f64 {
        self.arcs().map(|arc| arc.min_y()).fold(f64::INFINITY, f64::min)
    }

    fn arcs(&self) -> impl Iterator<Item = Arc> + '_ {
        (0..CONTROL).map(move |i| {
            let prev = self.control[(i + CONTROL - 1) % CONTROL];
            let p = self.control[i];
            let next = self.control[(i + 1) % CONTROL];
            Arc { p0: (prev + p) * 0.5, p1: p, p2: (p + next) * 0.5 }
        })
    }

    /// Signed distance in the section's plane: negative inside.
    ///
    /// The nearest on-curve end point bounds the distance from above, so only arcs whose
    /// control box is nearer need their cubic solved. The sign comes from the nearest point c:
    /// the open segment from c to q meets no curve point (one would be nearer), so q lies on
    /// the side of the curve that q − c points to, and the curve is tangent-continuous and
    /// counter-clockwise, so that side is the inside when q − c points left of the tangent at
    /// c. When that is too close to call (q on the curve or the tangent vanishing), the winding
    /// number decides ([`Section::winding`]).
    pub fn distance(&self, q: DVec2) -> f64 {
        let c = &self.control;
        let ends: [DVec2; CONTROL] = std::array::from_fn(|i| (c[i] + c[(i + 1) % CONTROL]) * 0.5);
        let mut nearest = (f64::INFINITY, 0, 0.0);
        for (i, m) in ends.iter().enumerate() {
            let d2 = (*m - q).length_squared();
            if d2 < nearest.0 {
                // End i is the end (t = 1) of arc i.
                nearest = (d2, i, 1.0);
            }
        }
        let arc = |i: usize| Arc { p0: ends[(i + CONTROL - 1) % CONTROL], p1: c[i], p2: ends[i] };
        for i in 0..CONTROL {
            let arc = arc(i);
            if arc.box_distance_squared(q) < nearest.0 {
                let (d2, t) = arc.nearest(q);
                if d2 < nearest.0 {
                    nearest = (d2, i, t);
                }
            }
        }
        let (d2, i, t) = nearest;
        let d = d2.sqrt();
        let arc = arc(i);
        let (tangent, away) = (arc.tangent(t), q - arc.at(t));
        let side = tangent.perp_dot(away);
        let inside = if side.abs() > 1e-9 * tangent.length() * away.length() && d > 0.0 {
            side > 0.0
        } else {
            self.winding(q, &ends) != 0
        };
        if inside { -d } else { d }
    }

    /// Winding number of the curve around q: crossings of the chords between on-curve points,
    /// except for arcs whose control triangle holds q (an arc and its chord bound a region
    /// inside that triangle, so elsewhere they cross the ray from q the same net number of
    /// times).
    fn winding(&self, q: DVec2, ends: &[DVec2; CONTROL]) -> i32 {
        (0..CONTROL)
            .map(|i| {
                let arc = Arc { p0: ends[(i + CONTROL - 1) % CONTROL], p1: self.control[i], p2: ends[i] };
                if arc.triangle_holds(q) { arc.winding(q) } else { chord_winding(arc.p0, arc.p2, q) }
            })
            .sum()
    }

    /// Checks the size and that no two arcs cross (each arc sampled as a polyline).
    pub fn check(&self) -> Result<(), SectionError> {
        self.check_size()?;
        self.check_crossings()
    }

    /// Checks that the control points are finite and not all on the axis.
    pub fn check_size(&self) -> Result<(), SectionError> {
        if self.control.iter().all(|c| c.is_finite()) && self.extent() > 0.0 {
            Ok(())
        } else {
            Err(SectionError::Degenerate)
        }
    }

    /// Checks that no two arcs cross, each sampled as a polyline. An invertible affine map of
    /// the control points maps the arcs, their samples and their crossings onto the image's,
    /// so a section scaled from a unit polygon ([`Section::blend`]) crosses itself exactly
    /// when the unit polygon does: one check per unit serves all its sizes.
    fn check_crossings(&self) -> Result<(), SectionError> {
        const STEPS: usize = 8;
        let polylines: Vec<Vec<DVec2>> =
            self.arcs().map(|a| (0..=STEPS).map(|k| a.at(k as f64 / STEPS as f64)).collect()).collect();
        for i in 0..CONTROL {
            for j in i + 1..CONTROL {
                let adjacent = j == i + 1 || (i == 0 && j == CONTROL - 1);
                for (s, a) in polylines[i].windows(2).enumerate() {
                    for (t, b) in polylines[j].windows(2).enumerate() {
                        // Adjacent arcs share an end point: skip the touching pieces.
                        let touching = adjacent
                            && ((j == i + 1 && s == STEPS - 1 && t == 0)
                                || (j != i + 1 && s == 0 && t == STEPS - 1));
                        if !touching && segments_cross(a[0], a[1], b[0], b[1]) {
                            return Err(SectionError::SelfIntersecting(i, j));
                        }
                    }
                }
            }
        }
        Ok(())
    }
}

/// The control polygon of a section in units of (radius, radius · ratio): the two types'
/// polygons, each sheared by `asymmetry` if it leans, averaged.
pub fn unit_blend(kinds: [ConduitType; 2], asymmetry: f32) -> [DVec2; CONTROL] {
    let sheared = |kind: ConduitType| {
        // Only vadose shapes lean: a free-surface stream undercuts the outside of its bends,
        // while phreatic tubes and beds dissolve evenly all round.
        let leans = matches!(kind, ConduitType::Canyon | ConduitType::Keyhole);
        let skew = if leans { asymmetry as f64 } else { 0.0 };
        // Asymmetry shears the upper half sideways (an undercut meander bend).
        unit_polygon(kind).map(|[x, y]| DVec2::new(x + skew * y.max(0.0) * 0.5, y))
    };
    let [k0, k1] = kinds;
    let first = sheared(k0);
    if k0 == k1 {
        return first;
    }
    let second = sheared(k1);
    std::array::from_fn(|i| (first[i] + second[i]) * 0.5)
}

/// The factors (radius, radius · ratio) that scale a unit polygon into a section.
pub fn scale_of(shape: Shape) -> DVec2 {
    let r = shape.radius as f64;
    DVec2::new(r, r * shape.ratio as f64)
}

/// Control polygons in half-widths, counter-clockwise from the bottom.
fn unit_polygon(kind: ConduitType) -> [[f64; 2]; CONTROL] {
    // Phreatic tube: a regular 12-gon whose B-spline lies within 0.03 % of the unit circle.
    let tube = |i: usize| {
        let a = -std::f64::consts::FRAC_PI_2 + i as f64 * std::f64::consts::TAU / CONTROL as f64;
        let r = 1.0 / TUBE_SCALE;
        [r * a.cos(), r * a.sin()]
    };
    match kind {
        ConduitType::Tube | ConduitType::Epikarst => std::array::from_fn(tube),
        // Keyhole: a tube at the bottom with a narrow vadose slot cut into its roof.
        ConduitType::Keyhole => [
            [0.0, -1.04],
            [0.55, -0.94],
            [0.98, -0.55],
            [1.08, 0.0],
            [0.7, 0.45],
            [0.3, 0.6],
            [0.28, 1.6],
            [-0.28, 1.6],
            [-0.3, 0.6],
            [-0.7, 0.45],
            [-1.08, 0.0],
            [-0.98, -0.55],
        ],
        // Canyon: tall and narrow, slightly wider at the top where it started.
        ConduitType::Canyon => [
            [0.0, -1.0],
            [0.35, -0.95],
            [0.45, -0.5],
            [0.5, 0.0],
            [0.6, 0.5],
            [0.7, 0.95],
            [0.0, 1.05],
            [-0.7, 0.95],
            [-0.6, 0.5],
            [-0.5, 0.0],
            [-0.45, -0.5],
            [-0.35, -0.95],
        ],
        // Bed (bedding-plane conduit): wide, low, flat floor and gently arched roof.
        ConduitType::Bed => [
            [0.0, -0.42],
            [0.7, -0.42],
            [1.1, -0.35],
            [1.2, 0.0],
            [1.0, 0.3],
            [0.55, 0.42],
            [0.0, 0.48],
            [-0.55, 0.42],
            [-1.0, 0.3],
            [-1.2, 0.0],
            [-1.1, -0.35],
            [-0.7, -0.42],
        ],
        // Passage (inclined): an oval with a flattened floor of breakdown.
        ConduitType::Passage | ConduitType::Chamber => [
            [0.0, -0.9],
            [0.6, -0.88],
            [1.05, -0.6],
            [1.15, 0.0],
            [1.0, 0.6],
            [0.55, 1.0],
            [0.0, 1.1],
            [-0.55, 1.0],
            [-1.0, 0.6],
            [-1.15, 0.0],
            [-1.05, -0.6],
            [-0.6, -0.88],
        ],
    }
}

/// Mean radius of the tube B-spline for a unit circumradius 12-gon: its curve is scaled by
/// this so that a tube section of radius r is the circle of radius r within 0.03 %.
const TUBE_SCALE: f64 = 0.96622;

/// One quadratic Bézier arc.
#[derive(Debug, Clone, Copy)]
struct Arc {
    p0: DVec2,
    p1: DVec2,
    p2: DVec2,
}

impl Arc {
    fn at(&self, t: f64) -> DVec2 {
        let s = 1.0 - t;
        self.p0 * (s * s) + self.p1 * (2.0 * s * t) + self.p2 * (t * t)
    }

    fn box_distance_squared(&self, q: DVec2) -> f64 {
        let lo = self.p0.min(self.p1).min(self.p2);
        let hi = self.p0.max(self.p1).max(self.p2);
        (lo - q).max(q - hi).max(DVec2::ZERO).length_squared()
    }

    fn min_y(&self) -> f64 {
        let (a, b) = (self.p1.y - self.p0.y, self.p0.y - 2.0 * self.p1.y + self.p2.y);
        let mut y = self.p0.y.min(self.p2.y);
        if b > 0.0 {
            let t = -a / b;
            if (0.0..=1.0).contains(&t) {
                y = y.min(self.at(t).y);
            }
        }
        y
    }

    /// min over t ∈ [0, 1] of |B(t) − q|²: B(t) = p0 + 2at + bt², the stationary points solve
    /// (b·b)t³ + 3(a·b)t² + (2a·a + d·b)t + d·a = 0 with d = p0 − q.
    /// (min over t ∈ [0, 1] of |B(t) − q|², a t where it is reached).
    fn nearest(&self, q: DVec2) -> (f64, f64) {
        let a = self.p1 - self.p0;
        let b = self.p0 - 2.0 * self.p1 + self.p2;
        let d = self.p0 - q;
        let (start, end) = (d.length_squared(), (self.p2 - q).length_squared());
        let mut best = if end < start { (end, 1.0) } else { (start, 0.0) };
        let coefficients = [b.dot(b), 3.0 * a.dot(b), 2.0 * a.dot(a) + d.dot(b), d.dot(a)];
        for t in cubic_roots(coefficients).iter() {
            let t = polish(coefficients, t).clamp(0.0, 1.0);
            let d2 = (self.at(t) - q).length_squared();
            if d2 < best.0 {
                best = (d2, t);
            }
        }
        best
    }

    /// B′(t).
    fn tangent(&self, t: f64) -> DVec2 {
        let a = self.p1 - self.p0;
        let b = self.p0 - 2.0 * self.p1 + self.p2;
        (a + b * t) * 2.0
    }

    /// Whether q lies in the closed control triangle (p0, p1, p2).
    fn triangle_holds(&self, q: DVec2) -> bool {
        let (a, b, c) = (
            (self.p1 - self.p0).perp_dot(q - self.p0),
            (self.p2 - self.p1).perp_dot(q - self.p1),
            (self.p0 - self.p2).perp_dot(q - self.p2),
        );
        (a >= 0.0 && b >= 0.0 && c >= 0.0) || (a <= 0.0 && b <= 0.0 && c <= 0.0)
    }

    /// Signed crossings of the ray from q towards +x (±1 per crossing, by direction).
    fn winding(&self, q: DVec2) -> i32 {
        let a = self.p1.y - self.p0.y;
        let b = self.p0.y - 2.0 * self.p1.y + self.p2.y;
        let c = self.p0.y - q.y;
        let mut w = 0;
        for t in quadratic_roots(b, 2.0 * a, c).iter() {
            // Half-open [0, 1): a crossing at a shared end point counts once.
            if (0.0..1.0).contains(&t) && self.at(t).x > q.x {
                let dy = 2.0 * a + 2.0 * b * t;
                w += if dy > 0.0 {
                    1
                } else if dy < 0.0 {
                    -1
                } else {
                    0
                };
            }
        }
        w
    }
}

/// Signed crossings of the ray from q towards +x by the segment p0 p2, with the arcs'
/// convention (a crossing at the start counts, one at the end does not).
fn chord_winding(p0: DVec2, p2: DVec2, q: DVec2) -> i32 {
    let dy = p2.y - p0.y;
    if dy == 0.0 {
        return 0;
    }
    let t = (q.y - p0.y) / dy;
    if (0.0..1.0).contains(&t) && p0.x + (p2.x - p0.x) * t > q.x { if dy > 0.0 { 1 } else { -1 } } else { 0 }
}

/// Up to three real roots, without allocating.
#[derive(Debug, Clone, Copy, Default)]
struct Roots {
    values: [f64; 3],
    len: usize,
}

impl Roots {
    fn of(values: &[f64]) -> Self {
        let mut r = Roots::default();
        r.values[..values.len()].copy_from_slice(values);
        r.len = values.len();
        r
    }

    fn iter(&self) -> impl Iterator<Item = f64> + '_ {
        self.values[..self.len].iter().copied()
    }
}

/// Real roots of at² + bt + c.
fn quadratic_roots(a: f64, b: f64, c: f64) -> Roots {
    if a.abs() < 1e-12 * (b.abs() + c.abs()).max(1e-300) {
        return if b != 0.0 { Roots::of(&[-c / b]) } else { Roots::default() };
    }
    let disc = b * b - 4.0 * a * c;
    if disc < 0.0 {
        return Roots::default();
    }
    // Numerically stable pair.
    let s = disc.sqrt();
    let q = -0.5 * (b + b.signum() * s);
    if q == 0.0 {
        return Roots::of(&[0.0]);
    }
    Roots::of(&[q / a, c / q])
}

/// Real roots of k[0]t³ + k[1]t² + k[2]t + k[3] (approximate; polished by [`polish`]).
fn cubic_roots(k: [f64; 4]) -> Roots {
    let scale = k.iter().fold(0.0f64, |m, v| m.max(v.abs()));
    if k[0].abs() <= 1e-9 * scale {
        return quadratic_roots(k[1], k[2], k[3]);
    }
    let (a, b, c) = (k[1] / k[0], k[2] / k[0], k[3] / k[0]);
    // t = x − a/3: x³ + px + q = 0.
    let p = b - a * a / 3.0;
    let q = 2.0 * a * a * a / 27.0 - a * b / 3.0 + c;
    let shift = -a / 3.0;
    let disc = q * q / 4.0 + p * p * p / 27.0;
    if disc > 0.0 {
        let s = disc.sqrt();
        Roots::of(&[cube_root(-q / 2.0 + s) + cube_root(-q / 2.0 - s) + shift])
    } else {
        let r = (-p / 3.0).max(0.0).sqrt();
        let phi = if r > 0.0 { (-q / (2.0 * r * r * r)).clamp(-1.0, 1.0).acos() } else { 0.0 };
        let root = |i: f64| 2.0 * r * ((phi + std::f64::consts::TAU * i) / 3.0).cos() + shift;
        Roots::of(&[root(0.0), root(1.0), root(2.0)])
    }
}

/// ∛x to a few ulps: a first guess from the bits (the exponent divided by three, within about
/// 3 %), then three Halley steps, each cubing the relative error. `f64::cbrt` is a software
/// routine here (correctly rounded, with an emulated fused multiply-add), a tenth of the
/// sweeps' distance; the roots are polished after anyway. Zero, subnormals, very large values
/// and NaN go to `f64::cbrt`.
fn cube_root(x: f64) -> f64 {
    let a = x.abs();
    if a.is_nan() || a <= 1e-290 || a >= 1e290 {
        return x.cbrt();
    }
    let mut y = f64::from_bits(a.to_bits() / 3 + 0x2A9F_7893_782D_A1CE);
    for _ in 0..3 {
        let y3 = y * y * y;
        y *= (y3 + 2.0 * a) / (2.0 * y3 + a);
    }
    y.copysign(x)
}

/// Two Newton steps on the cubic, guarded against flat derivatives.
fn polish(k: [f64; 4], mut t: f64) -> f64 {
    for _ in 0..2 {
        let f = ((k[0] * t + k[1]) * t + k[2]) * t + k[3];
        let df = (3.0 * k[0] * t + 2.0 * k[1]) * t + k[2];
        if df.abs() > 1e-300 {
            let next = t - f / df;
            if next.is_finite() {
                t = next;
            }
        }
    }
    t
}

/// Whether the segments ab and cd cross (proper or touching).
fn segments_cross(a: DVec2, b: DVec2, c: DVec2, d: DVec2) -> bool {
    let side = |p: DVec2, q: DVec2, r: DVec2| (q - p).perp_dot(r - p);
    let (d1, d2) = (side(c, d, a), side(c, d, b));
    let (d3, d4) = (side(a, b, c), side(a, b, d));
    (d1 * d2 <= 0.0) && (d3 * d4 <= 0.0) && !(d1 == 0.0 && d2 == 0.0 && d3 == 0.0 && d4 == 0.0)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn shape(radius: f32) -> Shape {
        Shape { radius, ratio: 1.0, asymmetry: 0.0 }
    }

    /// Brute-force distance: dense sampling of the curve, sign by a polygon crossing test.
    fn brute(section: &Section, q: DVec2) -> f64 {
        let pts: Vec<DVec2> =
            section.arcs().flat_map(|a| (0..400).map(move |k| a.at(k as f64 / 400.0))).collect();
        let d = pts.iter().map(|p| p.distance(q)).fold(f64::INFINITY, f64::min);
        let mut inside = false;
        for (i, a) in pts.iter().enumerate() {
            let b = pts[(i + 1) % pts.len()];
            if (a.y > q.y) != (b.y > q.y) && q.x < a.x + (q.y - a.y) / (b.y - a.y) * (b.x - a.x) {
                inside = !inside;
            }
        }
        if inside { -d } else { d }
    }

    #[test]
    fn every_type_matches_brute_force_and_is_simple() {
        for kind in ConduitType::ALL {
            let s = Section::of(kind, Shape { radius: 2.0, ratio: 1.2, asymmetry: 0.3 });
            s.check().unwrap();
            for i in 0..400 {
                let q = DVec2::new((i % 20) as f64 * 0.31 - 3.1, (i / 20) as f64 * 0.37 - 3.5);
                let (f, g) = (s.distance(q), brute(&s, q));
                assert!((f - g).abs() < 2e-3, "{kind:?} at {q}: {f} vs {g}");
                assert!(f.signum() == g.signum() || g.abs() < 1e-3, "{kind:?} sign at {q}");
            }
        }
    }

    #[test]
    fn the_tube_is_a_circle() {
        let s = Section::of(ConduitType::Tube, shape(3.0));
        for i in 0..100 {
            let a = i as f64 * 0.0628;
            let q = DVec2::new(a.cos(), a.sin()) * (i as f64 * 0.07);
            assert!((s.distance(q) - (q.length() - 3.0)).abs() < 3.0 * 4e-4, "{q}: {}", s.distance(q));
        }
    }

    #[test]
    fn the_cube_root_is_cbrt_to_a_few_ulps() {
        let mut x = 1e-300;
        while x < 1e300 {
            for v in [x, -x, x * 1.37, -x * 2.9] {
                let (ours, std) = (cube_root(v), v.cbrt());
                assert!((ours - std).abs() <= 4.0 * f64::EPSILON * std.abs(), "{v}: {ours} vs {std}");
            }
            x *= 3.3;
        }
        assert_eq!(cube_root(0.0), 0.0);
        assert_eq!(cube_root(-8.0), -2.0);
        assert!(cube_root(f64::NAN).is_nan());
    }

    #[test]
    fn only_vadose_sections_lean() {
        let lean = Shape { radius: 1.0, ratio: 1.0, asymmetry: 0.5 };
        for kind in ConduitType::ALL {
            let (straight, leaning) = (Section::of(kind, shape(1.0)), Section::of(kind, lean));
            let leans = matches!(kind, ConduitType::Canyon | ConduitType::Keyhole);
            assert_eq!(straight != leaning, leans, "{kind:?}");
        }
    }

    #[test]
    fn self_intersection_is_refused() {
        let mut s = Section::of(ConduitType::Tube, shape(1.0));
        s.control.swap(2, 8);
        assert!(matches!(s.check(), Err(SectionError::SelfIntersecting(..))));
        let flat = Section::of(ConduitType::Tube, shape(0.0));
        assert_eq!(flat.check(), Err(SectionError::Degenerate));
    }
}
