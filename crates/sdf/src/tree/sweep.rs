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
//! A run of sweeps along one straight segment (a passage profile's pieces, see
//! [`SweepTable::push_run`]) is one leaf: the section moves piecewise linearly through the
//! nodes' sections and the extrusion is capped at the run's two ends only. The boundary then
//! moves at most k = the largest of the pieces' k per metre, and the same argument gives the
//! √(1 + k²) factor. Caps between the pieces would bound the depth inside the passage to half a
//! piece, which is what keeps the mesher from proving the cells inside a passage empty.
//!
//! Frame: the section's y axis is the world's up projected perpendicular to ab (x for vertical
//! shafts), its x axis points to the right looking from a to b.

use std::collections::HashMap;

use glam::{DVec2, DVec3};
use serde::{Deserialize, Serialize};

use karst_skeleton::ConduitType;

use crate::tree::section::{CONTROL, Section, SectionError, Shape, unit_blend};

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

    /// The key of the unit polygon the section scales ([`unit_blend`]'s arguments).
    fn unit_key(&self) -> ([u8; 2], u32) {
        (self.kinds.map(|k| k as u8), self.shape.asymmetry.to_bits())
    }
}

/// [`Section::check`] of many specs' sections, the crossings checked once per unit polygon:
/// a section is its unit polygon scaled by (radius, radius · ratio) with positive factors, an
/// invertible affine map (see `Section::check_crossings`). On a real terrain's sdf.bin this
/// is 68,000 sweeps' two sections each against a few hundred units.
#[derive(Debug, Default)]
pub struct SectionChecks(HashMap<([u8; 2], u32), Result<(), SectionError>>);

impl SectionChecks {
    pub fn check(&mut self, spec: &SectionSpec) -> Result<(), SectionError> {
        let section = spec.section();
        section.check_size()?;
        if !(spec.shape.radius > 0.0 && spec.shape.ratio > 0.0) {
            // Not an invertible scaling: the section checked as it is.
            return section.check();
        }
        *self
            .0
            .entry(spec.unit_key())
            .or_insert_with(|| Section { control: unit_blend(spec.kinds, spec.shape.asymmetry) }.check())
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

/// A sweep leaf: its first node and its number of pieces (its nodes follow the first), its
/// Lipschitz factor 1/√(1 + k²) rounded down and the largest control-point distance to the
/// axis rounded up (f32).
#[derive(Debug, Clone, Copy)]
pub struct SweepLeaf {
    pub node: u32,
    pub pieces: u32,
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
        let key = spec.unit_key();
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
        let pair = pair_key(&start, &end);
        let node = match self.pair_index.get(&pair) {
            Some(&i) => i,
            None => self.append(start, end, pair),
        };
        self.finish(SweepLeaf { node, pieces: 1, scale: 1.0, extent: 0.0 })
    }

    /// One leaf for the consecutive pieces `specs` of one straight segment (each piece starts
    /// where the one before ends), capped at the run's ends only. Each piece's nodes stay
    /// shared with a later sweep of the same piece (its water).
    pub fn push_run(&mut self, specs: &[SweepSpec]) -> SweepLeaf {
        if specs.len() == 1 {
            return self.push(&specs[0]);
        }
        let mut first = None;
        for spec in specs {
            let (start, end) = (self.node(spec.a, &spec.start), self.node(spec.b, &spec.end));
            let pair = pair_key(&start, &end);
            first.get_or_insert(self.append(start, end, pair));
        }
        let node = first.expect("a run has pieces");
        self.finish(SweepLeaf { node, pieces: specs.len() as u32, scale: 1.0, extent: 0.0 })
    }

    /// Appends the nodes of a piece (its start only when the last node is not already it);
    /// returns the index of its start node.
    fn append(&mut self, start: SweepNode, end: SweepNode, pair: [u32; 12]) -> u32 {
        let continues = self
            .nodes
            .last()
            .is_some_and(|last| node_key(last) == node_key(&start) && last.unit == start.unit);
        if !continues {
            self.nodes.push(start);
        }
        self.nodes.push(end);
        let i = (self.nodes.len() - 2) as u32;
        self.pair_index.entry(pair).or_insert(i);
        i
    }

    /// `leaf` with its Lipschitz factor (from its fastest piece) and its extent.
    fn finish(&self, mut leaf: SweepLeaf) -> SweepLeaf {
        let sweep = self.sweep(&leaf);
        let k = (0..sweep.nodes.len() - 1).map(|j| sweep.taper(j)).fold(0.0, f64::max);
        let extent = (0..sweep.nodes.len())
            .flat_map(|e| (0..CONTROL).map(move |i| (e, i)))
            .map(|(e, i)| sweep.control(e, i).length())
            .fold(0.0, f64::max);
        leaf.scale = round_down(1.0 / (1.0 + k * k).sqrt());
        leaf.extent = -round_down(-extent);
        leaf
    }

    /// The sweep of `leaf`, ready to evaluate.
    pub fn sweep(&self, leaf: &SweepLeaf) -> Sweep<'_> {
        let nodes = &self.nodes[leaf.node as usize..=(leaf.node + leaf.pieces) as usize];
        let (a, b) = (to_dvec(nodes[0].p), to_dvec(nodes[nodes.len() - 1].p));
        let length = a.distance(b);
        let axis = (b - a) / length;
        let (right, up) = frame(axis);
        Sweep {
            a,
            axis,
            length,
            right,
            up,
            nodes,
            units: &self.units,
            scale: leaf.scale as f64,
            extent: leaf.extent as f64,
        }
    }

    /// The end points of `leaf`'s axis.
    pub fn ends(&self, leaf: &SweepLeaf) -> (DVec3, DVec3) {
        let last = (leaf.node + leaf.pieces) as usize;
        (to_dvec(self.nodes[leaf.node as usize].p), to_dvec(self.nodes[last].p))
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

fn node_key(n: &SweepNode) -> [u32; 5] {
    [n.p[0], n.p[1], n.p[2], n.shape[0], n.shape[1]].map(f32::to_bits)
}

/// The key of a piece: its two nodes' positions, shapes and unit polygons.
fn pair_key(start: &SweepNode, end: &SweepNode) -> [u32; 12] {
    let mut pair = [0; 12];
    pair[..5].copy_from_slice(&node_key(start));
    pair[5] = start.unit;
    pair[6..11].copy_from_slice(&node_key(end));
    pair[11] = end.unit;
    pair
}

/// The largest f32 not above `v`.
fn round_down(v: f64) -> f32 {
    let f = v as f32;
    if f as f64 > v { f.next_down() } else { f }
}

/// A sweep ready to evaluate, built on the fly from its nodes.
#[derive(Debug, Clone)]
pub struct Sweep<'a> {
    a: DVec3,
    axis: DVec3,
    length: f64,
    right: DVec3,
    up: DVec3,
    /// The run's nodes, first to last (two for a single sweep).
    nodes: &'a [SweepNode],
    units: &'a [Unit],
    /// 1/√(1 + k²).
    scale: f64,
    /// At least the largest control-point distance to the axis.
    extent: f64,
}

impl Sweep<'_> {
    /// Control point i of node e of the run.
    fn control(&self, e: usize, i: usize) -> DVec2 {
        let n = &self.nodes[e];
        self.units[n.unit as usize].control[i] * shape_scale(n)
    }

    /// The control box of node e: (lo, hi).
    fn control_box(&self, e: usize) -> (DVec2, DVec2) {
        let (n, scale) = (&self.nodes[e], shape_scale(&self.nodes[e]));
        let unit = &self.units[n.unit as usize];
        (unit.lo * scale, unit.hi * scale)
    }

    /// Abscissa of node e along the axis: the ends at 0 and the length exactly, the inner
    /// nodes (on the segment up to f32 rounding) projected on the axis.
    fn abscissa(&self, e: usize) -> f64 {
        if e == 0 {
            0.0
        } else if e == self.nodes.len() - 1 {
            self.length
        } else {
            (to_dvec(self.nodes[e].p) - self.a).dot(self.axis)
        }
    }

    /// How fast piece j's section moves: its largest control-point move per metre of axis.
    fn taper(&self, j: usize) -> f64 {
        let span = self.abscissa(j + 1) - self.abscissa(j);
        (0..CONTROL).map(|i| self.control(j, i).distance(self.control(j + 1, i))).fold(0.0, f64::max) / span
    }

    /// The piece at abscissa l (the first or last beyond the ends) and the fraction of the way
    /// along it, clamped to [0, 1].
    fn piece(&self, l: f64) -> (usize, f64) {
        let (mut lo, mut hi) = (0, self.nodes.len() - 1);
        while hi - lo > 1 {
            let mid = (lo + hi) / 2;
            if self.abscissa(mid) <= l {
                lo = mid;
            } else {
                hi = mid;
            }
        }
        let (l0, l1) = (self.abscissa(lo), self.abscissa(hi));
        (lo, ((l - l0) / (l1 - l0)).clamp(0.0, 1.0))
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
        let (j, t) = self.piece(l);
        let f = self.section_at(j, t).distance(q);
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
    /// distance to the union of the control boxes of the piece's end sections and at least
    /// |q| − extent.
    #[cfg(test)]
    pub fn lower_bound(&self, p: DVec3) -> f64 {
        let (l, q) = self.local(p);
        self.lower_bound_local(l, q)
    }

    /// [`Sweep::lower_bound`] at local coordinates.
    pub fn lower_bound_local(&self, l: f64, q: DVec2) -> f64 {
        let (j, _) = self.piece(l);
        let ((lo0, hi0), (lo1, hi1)) = (self.control_box(j), self.control_box(j + 1));
        let (lo, hi) = (lo0.min(lo1), hi0.max(hi1));
        let d = (lo - q).max(q - hi);
        let boxed = d.max(DVec2::ZERO).length() + d.max_element().min(0.0);
        self.combine(boxed.max(q.length() - self.extent), l)
    }

    /// Height of p above the axis, along the section's up direction.
    pub fn height(&self, p: DVec3) -> f64 {
        (p - self.a).dot(self.up)
    }

    /// The section at fraction t of the way along piece j.
    fn section_at(&self, j: usize, t: f64) -> Section {
        Section { control: std::array::from_fn(|i| self.control(j, i).lerp(self.control(j + 1, i), t)) }
    }
}

/// A node's (radius, radius·ratio): the scale of its unit polygon.
fn shape_scale(n: &SweepNode) -> DVec2 {
    DVec2::new(n.shape[0] as f64, n.shape[0] as f64 * n.shape[1] as f64)
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
    fn a_unit_checked_once_gives_every_size_the_verdict_of_its_own_check() {
        let mut checks = SectionChecks::default();
        for k0 in ConduitType::ALL {
            for k1 in ConduitType::ALL {
                for asymmetry in [-1.0, -0.3, 0.0, 0.7, 1.0] {
                    for (radius, ratio) in
                        [(0.4, 0.2), (1.0, 1.0), (7.5, 3.0), (300.0, 0.05), (0.0, 1.0), (2.0, 0.0)]
                    {
                        let spec = SectionSpec { kinds: [k0, k1], shape: Shape { radius, ratio, asymmetry } };
                        assert_eq!(checks.check(&spec), spec.section().check(), "{spec:?}");
                    }
                }
            }
        }
        let flat = SectionSpec {
            kinds: [ConduitType::Tube; 2],
            shape: Shape { radius: 1.0, ratio: 0.0, asymmetry: 0.0 },
        };
        assert_eq!(checks.check(&flat), flat.section().check());
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

    /// Pieces of a straight segment every 2 m, a pinch and a room among them.
    fn run(table: &mut SweepTable) -> (SweepLeaf, Vec<SweepSpec>) {
        let radii = [2.0, 1.0, 0.4, 1.5, 3.0, 2.0];
        let at = |i: usize| [2.0 * i as f32, 0.5 * i as f32, 0.0];
        let pieces: Vec<SweepSpec> = radii
            .windows(2)
            .enumerate()
            .map(|(i, r)| SweepSpec {
                a: at(i),
                b: at(i + 1),
                start: spec(ConduitType::Canyon, r[0]),
                end: spec(ConduitType::Canyon, r[1]),
            })
            .collect();
        (table.push_run(&pieces), pieces)
    }

    #[test]
    fn a_run_is_one_lipschitz_and_open_from_piece_to_piece() {
        let mut table = SweepTable::default();
        let (leaf, pieces) = run(&mut table);
        let singles: Vec<SweepLeaf> = pieces.iter().map(|p| table.push(p)).collect();
        let s = table.sweep(&leaf);
        assert_lipschitz(
            |p| s.distance(p),
            Pairs::new(4, 8.0, 1.5).around(DVec3::new(5.0, 1.2, 0.0)),
            20_000,
        );
        for (p, _) in Pairs::new(5, 8.0, 0.0).around(DVec3::new(5.0, 1.2, 0.0)).take(5000) {
            assert!(s.lower_bound(p) <= s.distance(p) + 1e-9, "{p}");
        }
        // At a joint between pieces, inside the passage, the run is as deep as the section
        // (times its factor); each single piece is cut there by its flat cap.
        let joint = DVec3::new(6.0, 1.5, 0.5);
        let single = singles.iter().map(|l| table.sweep(l).distance(joint)).fold(f64::INFINITY, f64::min);
        let depth = s.section_at(3, 0.0).distance(s.local(joint).1) * s.scale;
        assert!((s.distance(joint) - depth).abs() < 1e-9, "{} vs {depth}", s.distance(joint));
        assert!(single > -0.01 && s.distance(joint) < -0.5, "run {} single {single}", s.distance(joint));
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
