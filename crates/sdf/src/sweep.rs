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

use std::collections::HashMap;

use glam::{DVec2, DVec3};
use serde::{Deserialize, Serialize};

use karst_skeleton::ConduitType;

use crate::section::{CONTROL, Section, Shape, unit_blend};

/// A section as the artifact stores it: the blend, half and half, of two conduit types' shapes
/// (the types of the segments meeting at a node), with one shape.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct SectionSpec {
    pub kinds: [ConduitType; 2],
    pub shape: Shape,
}

impl SectionSpec {
    pub fn section(&self) -> Section {
        Section::blend(self.kinds, self.shape)
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

impl SweepSpec {
    /// Lowest point of the end sections (y of the floor, relative to the axis); the sections
    /// in between are convex combinations of theirs.
    pub fn floor(&self) -> f64 {
        self.start.section().floor().min(self.end.section().floor())
    }
}

/// A section's unit polygon (see [`unit_blend`]) with its control box.
#[derive(Debug, Clone)]
pub struct Unit {
    control: [DVec2; CONTROL],
    lo: DVec2,
    hi: DVec2,
}

/// An end of a sweep as evaluation keeps it: the node position, the section's radius and
/// ratio, and its unit polygon (an index into [`SweepTable::units`]). 24 bytes; consecutive
/// sweeps of a conduit, and a segment's karst sweep and water piece, share their nodes.
#[derive(Debug, Clone, Copy)]
pub struct SweepNode {
    p: [f32; 3],
    shape: [f32; 2],
    unit: u32,
}

/// A sweep leaf: its first node (the second follows it), its Lipschitz factor 1/√(1 + k²)
/// rounded down and the largest control-point distance to the axis rounded up (f32).
#[derive(Debug, Clone, Copy)]
pub struct SweepLeaf {
    pub node: u32,
    pub scale: f32,
    pub extent: f32,
}

/// The nodes and unit polygons the sweep leaves refer to.
#[derive(Debug, Clone, Default)]
pub struct SweepTable {
    pub units: Vec<Unit>,
    pub nodes: Vec<SweepNode>,
    unit_index: HashMap<([u8; 2], u32), u32>,
    pair_index: HashMap<[u32; 12], u32>,
}

impl SweepTable {
    fn unit(&mut self, spec: &SectionSpec) -> u32 {
        let key = (spec.kinds.map(|k| k as u8), spec.shape.asymmetry.to_bits());
        if let Some(&i) = self.unit_index.get(&key) {
            return i;
        }
        let control = unit_blend(spec.kinds, spec.shape.asymmetry);
        let lo = control.iter().fold(DVec2::INFINITY, |m, c| m.min(*c));
        let hi = control.iter().fold(DVec2::NEG_INFINITY, |m, c| m.max(*c));
        self.units.push(Unit { control, lo, hi });
        let i = (self.units.len() - 1) as u32;
        self.unit_index.insert(key, i);
        i
    }

    fn node(&mut self, p: [f32; 3], spec: &SectionSpec) -> SweepNode {
        SweepNode { p, shape: [spec.shape.radius, spec.shape.ratio], unit: self.unit(spec) }
    }

    /// The leaf of `spec`, sharing nodes with the previous sweep when it continues it, and with
    /// an earlier sweep of the same segment.
    pub fn push(&mut self, spec: &SweepSpec) -> SweepLeaf {
        let (start, end) = (self.node(spec.a, &spec.start), self.node(spec.b, &spec.end));
        let key = |n: &SweepNode| [n.p[0], n.p[1], n.p[2], n.shape[0], n.shape[1]].map(f32::to_bits);
        let pair: [u32; 12] = {
            let (k0, k1) = (key(&start), key(&end));
            let mut pair = [0; 12];
            pair[..5].copy_from_slice(&k0);
            pair[5] = start.unit;
            pair[6..11].copy_from_slice(&k1);
            pair[11] = end.unit;
            pair
        };
        let node = match self.pair_index.get(&pair) {
            Some(&i) => i,
            None => {
                let continues =
                    self.nodes.last().is_some_and(|last| key(last) == key(&start) && last.unit == start.unit);
                if !continues {
                    self.nodes.push(start);
                }
                self.nodes.push(end);
                let i = (self.nodes.len() - 2) as u32;
                self.pair_index.insert(pair, i);
                i
            }
        };
        let mut leaf = SweepLeaf { node, scale: 1.0, extent: 0.0 };
        let sweep = self.sweep(&leaf);
        let k = (0..CONTROL).map(|i| sweep.control(0, i).distance(sweep.control(1, i))).fold(0.0, f64::max)
            / sweep.length;
        let extent = (0..CONTROL)
            .map(|i| sweep.control(0, i).length().max(sweep.control(1, i).length()))
            .fold(0.0, f64::max);
        leaf.scale = round_down(1.0 / (1.0 + k * k).sqrt());
        leaf.extent = -round_down(-extent);
        leaf
    }

    /// The sweep of `leaf`, ready to evaluate.
    pub fn sweep(&self, leaf: &SweepLeaf) -> Sweep<'_> {
        let (n0, n1) = (&self.nodes[leaf.node as usize], &self.nodes[leaf.node as usize + 1]);
        let (a, b) = (to_dvec(n0.p), to_dvec(n1.p));
        let length = a.distance(b);
        let axis = (b - a) / length;
        let (right, up) = frame(axis);
        let scale_of = |n: &SweepNode| DVec2::new(n.shape[0] as f64, n.shape[0] as f64 * n.shape[1] as f64);
        Sweep {
            a,
            axis,
            length,
            right,
            up,
            units: [&self.units[n0.unit as usize], &self.units[n1.unit as usize]],
            scales: [scale_of(n0), scale_of(n1)],
            scale: leaf.scale as f64,
            extent: leaf.extent as f64,
        }
    }

    /// The end points of `leaf`'s axis.
    pub fn ends(&self, leaf: &SweepLeaf) -> (DVec3, DVec3) {
        (to_dvec(self.nodes[leaf.node as usize].p), to_dvec(self.nodes[leaf.node as usize + 1].p))
    }

    /// Axis-aligned bounds of the swept volume of `leaf`, without building the sweep.
    pub fn bounds(&self, leaf: &SweepLeaf) -> (DVec3, DVec3) {
        let (a, b) = self.ends(leaf);
        let r = DVec3::splat(leaf.extent as f64);
        (a.min(b) - r, a.max(b) + r)
    }

    /// Bytes held by the nodes and unit polygons.
    pub fn memory(&self) -> usize {
        self.nodes.len() * std::mem::size_of::<SweepNode>() + self.units.len() * std::mem::size_of::<Unit>()
    }
}

/// The largest f32 not above `v`.
fn round_down(v: f64) -> f32 {
    let f = v as f32;
    if f as f64 > v { f.next_down() } else { f }
}

/// A sweep ready to evaluate, built on the fly from its two nodes.
#[derive(Debug, Clone)]
pub struct Sweep<'a> {
    a: DVec3,
    axis: DVec3,
    length: f64,
    right: DVec3,
    up: DVec3,
    units: [&'a Unit; 2],
    scales: [DVec2; 2],
    /// 1/√(1 + k²).
    scale: f64,
    /// At least the largest control-point distance to the axis.
    extent: f64,
}

impl Sweep<'_> {
    /// Control point i of end e (0 at a, 1 at b).
    fn control(&self, e: usize, i: usize) -> DVec2 {
        self.units[e].control[i] * self.scales[e]
    }

    /// Position of p in the sweep's frame: (abscissa along ab, section-plane coordinates).
    pub fn local(&self, p: DVec3) -> (f64, DVec2) {
        let d = p - self.a;
        (d.dot(self.axis), DVec2::new(d.dot(self.right), d.dot(self.up)))
    }

    /// The 1-Lipschitz signed distance bound: negative inside.
    #[cfg(test)]
    pub fn distance(&self, p: DVec3) -> f64 {
        let (l, q) = self.local(p);
        self.distance_local(l, q)
    }

    /// [`Sweep::distance`] at the local coordinates of [`Sweep::local`].
    pub fn distance_local(&self, l: f64, q: DVec2) -> f64 {
        let t = (l / self.length).clamp(0.0, 1.0);
        let f = self.section_at(t).distance(q);
        self.combine(f, l)
    }

    /// The exact extrusion of a section value f at abscissa l, times the Lipschitz factor; it
    /// grows with f.
    fn combine(&self, f: f64, l: f64) -> f64 {
        let s = (-l).max(l - self.length);
        let g = f.max(s).min(0.0) + DVec2::new(f.max(0.0), s.max(0.0)).length();
        g * self.scale
    }

    /// A lower bound of [`Sweep::distance`]: the section value is at least the signed
    /// distance to the union of the end sections' control boxes and at least |q| − extent.
    #[cfg(test)]
    pub fn lower_bound(&self, p: DVec3) -> f64 {
        let (l, q) = self.local(p);
        self.lower_bound_local(l, q)
    }

    /// [`Sweep::lower_bound`] at local coordinates.
    pub fn lower_bound_local(&self, l: f64, q: DVec2) -> f64 {
        let lo = (self.units[0].lo * self.scales[0]).min(self.units[1].lo * self.scales[1]);
        let hi = (self.units[0].hi * self.scales[0]).max(self.units[1].hi * self.scales[1]);
        let d = (lo - q).max(q - hi);
        let boxed = d.max(DVec2::ZERO).length() + d.max_element().min(0.0);
        self.combine(boxed.max(q.length() - self.extent), l)
    }

    /// Height of p above the axis, along the section's up direction.
    pub fn height(&self, p: DVec3) -> f64 {
        (p - self.a).dot(self.up)
    }

    /// The section at fraction t of the way from a to b.
    fn section_at(&self, t: f64) -> Section {
        Section { control: std::array::from_fn(|i| self.control(0, i).lerp(self.control(1, i), t)) }
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

/// 1 − chord/length of a conduit's polyline: 0 for a straight conduit, 1 for a loop; above
/// `sdf.tortuosity` the conduit is swept segment by segment.
pub fn tortuosity(points: &[DVec3]) -> f64 {
    let length: f64 = points.windows(2).map(|w| w[0].distance(w[1])).sum();
    let chord = points[0].distance(points[points.len() - 1]);
    if length > 0.0 { 1.0 - chord / length } else { 0.0 }
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
        let mut table = SweepTable::default();
        let leaf = table.push(&SweepSpec {
            a,
            b,
            start: spec(ConduitType::Tube, 2.0),
            end: spec(ConduitType::Tube, 2.0),
        });
        let sweep = table.sweep(&leaf);
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
        let mut table = SweepTable::default();
        let leaves = [
            table.push(&SweepSpec {
                a: [0.0; 3],
                b: [6.0, 1.0, 0.5],
                start: spec(ConduitType::Keyhole, 2.0),
                end: spec(ConduitType::Canyon, 1.0),
            }),
            table.push(&SweepSpec {
                a: [0.0; 3],
                b: [0.0, 0.0, 5.0],
                start: spec(ConduitType::Bed, 1.0),
                end: spec(ConduitType::Passage, 2.5),
            }),
        ];
        for leaf in &leaves {
            let s = table.sweep(leaf);
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
