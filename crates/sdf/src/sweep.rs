//! The sweep primitive: a closed piecewise-quadratic cross-section swept along a segment ab
//! (Paris et al. 2021 §6.2 and appendix B), its section interpolated linearly from the start
//! section at a to the end section at b.
//!
//! With l the abscissa of p along ab, q its coordinates in the section plane and f_C the signed
//! 2D distance of appendix C to the section at clamp(l/|ab|, 0, 1), appendix B's distance
//! √(s² + d²) is the exterior case of the exact extrusion
//!   g(p) = min(max(f_C, s), 0) + |(max(f_C, 0), max(s, 0))|,  s = max(−l, l − |ab|),
//! which also covers the inside (negative, the nearer of the wall and the end caps).
//! A constant section gives an exact distance. A tapering section moves its boundary by at most
//! k = max_i |ΔP_i|/|ab| per metre along the axis (curve points are convex combinations of
//! control points), so g is √(1 + k²)-Lipschitz and g/√(1 + k²) is the 1-Lipschitz leaf.
//!
//! Frame: the section's y axis is the world's up projected perpendicular to ab (x for vertical
//! shafts), its x axis points to the right looking from a to b.

use glam::{DVec2, DVec3, Vec2};
use serde::{Deserialize, Serialize};

use karst_skeleton::ConduitType;

use crate::section::{CONTROL, Section, Shape};

/// A section as the artifact stores it: the blend, half and half, of two conduit types' shapes
/// (the types of the segments meeting at a node), with one shape.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct SectionSpec {
    pub kinds: [ConduitType; 2],
    pub shape: Shape,
}

impl SectionSpec {
    pub fn section(&self) -> Section {
        let [k0, k1] = self.kinds;
        let s0 = Section::of(k0, self.shape);
        if k0 == k1 { s0 } else { s0.lerp(&Section::of(k1, self.shape), 0.5) }
    }
}

/// A sweep as the artifact stores it.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct SweepSpec {
    pub a: [f32; 3],
    pub b: [f32; 3],
    pub start: SectionSpec,
    pub end: SectionSpec,
}

/// A sweep ready to evaluate.
#[derive(Debug, Clone)]
pub struct Sweep {
    a: DVec3,
    axis: DVec3,
    length: f64,
    right: DVec3,
    up: DVec3,
    /// The end sections' control points, in f32 (the sections are exactly these points).
    start: [Vec2; CONTROL],
    end: [Vec2; CONTROL],
    /// 1/√(1 + k²).
    scale: f64,
    /// The largest control-point distance to the axis.
    extent: f64,
}

impl Sweep {
    pub fn new(spec: &SweepSpec) -> Self {
        Self::between(to_dvec(spec.a), to_dvec(spec.b), spec.start.section(), spec.end.section())
    }

    /// The sweep from `start` at a to `end` at b (a ≠ b).
    pub fn between(a: DVec3, b: DVec3, start: Section, end: Section) -> Self {
        let (start, end) = (start.control.map(|c| c.as_vec2()), end.control.map(|c| c.as_vec2()));
        let (start, end) = (
            Section { control: start.map(|c| c.as_dvec2()) },
            Section { control: end.map(|c| c.as_dvec2()) },
        );
        let length = a.distance(b);
        let axis = (b - a) / length;
        let (right, up) = frame(axis);
        let k =
            start.control.iter().zip(&end.control).map(|(s, e)| s.distance(*e)).fold(0.0, f64::max) / length;
        let extent = start.extent().max(end.extent());
        let (start, end) = (start.control.map(|c| c.as_vec2()), end.control.map(|c| c.as_vec2()));
        Sweep { a, axis, length, right, up, start, end, scale: 1.0 / (1.0 + k * k).sqrt(), extent }
    }

    /// Position of p in the sweep's frame: (abscissa along ab, section-plane coordinates).
    fn local(&self, p: DVec3) -> (f64, DVec2) {
        let d = p - self.a;
        (d.dot(self.axis), DVec2::new(d.dot(self.right), d.dot(self.up)))
    }

    /// The 1-Lipschitz signed distance bound: negative inside.
    pub fn distance(&self, p: DVec3) -> f64 {
        let (l, q) = self.local(p);
        let t = (l / self.length).clamp(0.0, 1.0);
        let f = self.section_at(t).distance(q);
        let s = (-l).max(l - self.length);
        let g = f.max(s).min(0.0) + DVec2::new(f.max(0.0), s.max(0.0)).length();
        g * self.scale
    }

    /// A lower bound of [`Sweep::distance`], from the capsule of radius `extent` around ab.
    pub fn lower_bound(&self, p: DVec3) -> f64 {
        let (l, q) = self.local(p);
        let s = (-l).max(l - self.length).max(0.0);
        (DVec2::new(s, q.length()).length() - self.extent) * self.scale
    }

    /// Axis-aligned bounds of the swept volume.
    pub fn bounds(&self) -> (DVec3, DVec3) {
        let b = self.a + self.axis * self.length;
        let r = DVec3::splat(self.extent);
        (self.a.min(b) - r, self.a.max(b) + r)
    }

    /// Height of p above the axis, along the section's up direction.
    pub fn height(&self, p: DVec3) -> f64 {
        (p - self.a).dot(self.up)
    }

    /// Lowest point of the sections (y of the floor, relative to the axis).
    pub fn floor(&self) -> f64 {
        self.section_at(0.0).floor().min(self.section_at(1.0).floor())
    }

    /// The section at fraction t of the way from a to b.
    fn section_at(&self, t: f64) -> Section {
        let control = std::array::from_fn(|i| self.start[i].as_dvec2().lerp(self.end[i].as_dvec2(), t));
        Section { control }
    }
}

/// (right, up) for a conduit running along `axis`.
pub fn frame(axis: DVec3) -> (DVec3, DVec3) {
    let reference = if axis.z.abs() < 0.999 { DVec3::Z } else { DVec3::X };
    let up = (reference - axis * axis.dot(reference)).normalize();
    (axis.cross(up), up)
}

pub fn to_dvec(v: [f32; 3]) -> DVec3 {
    DVec3::new(v[0] as f64, v[1] as f64, v[2] as f64)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::Capsule;
    use crate::testing::{Pairs, assert_lipschitz};

    fn spec(kind: ConduitType, radius: f32) -> SectionSpec {
        SectionSpec { kinds: [kind, kind], shape: Shape { radius, ratio: 1.0, asymmetry: 0.0 } }
    }

    #[test]
    fn the_sweep_of_a_circle_is_a_capsule_with_flat_caps() {
        let (a, b) = ([1.0, 2.0, 3.0], [9.0, 4.0, 6.0]);
        let sweep = Sweep::new(&SweepSpec {
            a,
            b,
            start: spec(ConduitType::Tube, 2.0),
            end: spec(ConduitType::Tube, 2.0),
        });
        let capsule = Capsule { a: a.map(f64::from), b: b.map(f64::from), radius: 2.0 };
        // Within the slab the sweep is the capsule (a cylinder there), unless a flat cap is
        // nearer than the wall; beyond the caps the capsule is rounded and the sweep flat, so
        // the sweep is never below the capsule.
        for (p, _) in Pairs::new(3, 8.0, 0.0).around(DVec3::new(5.0, 3.0, 4.5)).take(5000) {
            let (l, _) = sweep.local(p);
            let (f, c) = (sweep.distance(p), capsule.distance(p));
            let cap = l.min(sweep.length - l);
            if cap >= 0.0 && (c >= 0.0 || cap >= -c) {
                assert!((f - c).abs() < 2.0 * 4e-4, "{p}: sweep {f}, capsule {c}");
            } else {
                assert!(f >= c - 1e-3, "{p}");
            }
        }
    }

    #[test]
    fn sweeps_are_one_lipschitz() {
        let sweeps = [
            Sweep::new(&SweepSpec {
                a: [0.0; 3],
                b: [6.0, 1.0, 0.5],
                start: spec(ConduitType::Keyhole, 2.0),
                end: spec(ConduitType::Canyon, 1.0),
            }),
            Sweep::new(&SweepSpec {
                a: [0.0; 3],
                b: [0.0, 0.0, 5.0],
                start: spec(ConduitType::Bed, 1.0),
                end: spec(ConduitType::Passage, 2.5),
            }),
        ];
        for s in &sweeps {
            assert_lipschitz(
                |p| s.distance(p),
                Pairs::new(9, 6.0, 1.5).around(DVec3::new(2.0, 0.0, 1.0)),
                20_000,
            );
            for (p, _) in Pairs::new(2, 9.0, 0.0).take(2000) {
                assert!(s.lower_bound(p) <= s.distance(p) + 1e-9);
            }
        }
    }
}
