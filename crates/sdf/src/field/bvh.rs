//! A bounding-volume hierarchy over the leaves, so that evaluating the union at a point visits
//! only the leaves that can be below the current minimum, and so that a whole box of space can
//! be bounded at once.
//!
//! Surface-area split (16 bins per axis; median split across the longest extent of the
//! leaves' centres when the centres fall in one bin) down to at most `LEAF`
//! leaves, then split further by kind (sphere, sweep, water, chamber, capsule), so that each
//! leaf node holds leaves of one kind: the leaves are stored by kind in tree order (no index
//! array, no per-leaf tag), and a leaf node names its kind and the range in that kind's array.
//! The binary tree is then collapsed into one with four children per node, their boxes side
//! by side in f32 rounded outwards: a visit reads two adjacent cache lines instead of one cache
//! miss per binary level, which is what evaluation at scattered points waits on. The traversal
//! visits the nearest child first and keeps each pushed child's box distance, so a child is
//! dropped without recomputing it once the minimum found so far is below it. Within a leaf
//! node of sweeps, the sweeps are taken in the order of a cheap lower bound (box and capsule),
//! and the exact sections are only computed while that bound is below the minimum.

use glam::{DVec3, Vec3, Vec4};

use crate::Capsule;
use crate::field::primitive::{
    CAPSULE, CHAMBER, Context, Leaf, SPHERE, SWEEP, WATER, WaterLeaf, capsule_value, chamber_value,
    signed_box_distance, sphere_value, sweep_floor, sweep_value, water_value,
};
use crate::tree::chamber::Chamber;
use crate::tree::sweep::SweepLeaf;

/// The count of a candidate that is a single capsule.
const ONE_CAPSULE: u32 = 1 | (CAPSULE as u32) << 16;

/// Leaves per BVH leaf node, at most: 16 rather than 8 halves the wide nodes (most of the
/// tree's memory) at the same evaluation speed.
const LEAF: usize = 16;

#[derive(Debug, Clone)]
struct Node {
    lo: Vec3,
    hi: Vec3,
    /// Leaf: first leaf in its kind's array; inner: the right child (the left one is next).
    first: u32,
    /// Leaf: number of leaves | kind << 16; 0 for an inner node.
    count: u32,
}

/// Four children's boxes (f32, structure of arrays, rounded outwards) and references: a child
/// is a wide node (`count` 0), a range of leaves (`count` = number | kind << 16) or empty
/// (an empty box, never visited). 128 bytes, two cache lines.
#[derive(Debug, Clone)]
#[repr(C, align(64))]
struct Wide {
    lo: [[f32; 4]; 3],
    hi: [[f32; 4]; 3],
    child: [u32; 4],
    count: [u32; 4],
}

/// A leaf node gathered by [`Bvh::near_box`]: its range of leaves (as in [`Wide`]) and its box.
#[derive(Debug, Clone, Copy)]
pub struct Candidate {
    first: u32,
    count: u32,
    lo: DVec3,
    hi: DVec3,
}

/// The hierarchy and its leaves, by kind, in tree order.
#[derive(Debug, Clone, Default)]
pub struct Bvh {
    /// The binary tree, while building.
    nodes: Vec<Node>,
    /// The tree with four children per node, made from the binary one; the root is first.
    wide: Vec<Wide>,
    /// Margin taken off the f32 box distances: more than their rounding error.
    slack: f64,
    spheres: Vec<[f32; 4]>,
    /// The conduit type of each sphere (its detail amplitude).
    sphere_types: Vec<u8>,
    sweeps: Vec<SweepLeaf>,
    sweep_types: Vec<u8>,
    water: Vec<WaterLeaf>,
    chambers: Vec<Chamber>,
    capsules: Vec<Capsule>,
}

impl Bvh {
    /// The hierarchy of `leaves`; `ctx` gives their boxes.
    pub fn build(leaves: Vec<Leaf>, ctx: &Context) -> Self {
        let bounds: Vec<(DVec3, DVec3)> = leaves.iter().map(|l| l.bounds(ctx)).collect();
        let classes: Vec<u8> = leaves.iter().map(Leaf::kind).collect();
        let mut order: Vec<u32> = (0..leaves.len() as u32).collect();
        let mut slots: Vec<Option<Leaf>> = leaves.into_iter().map(Some).collect();
        let mut bvh = Bvh { nodes: Vec::with_capacity(slots.len() / 2 + 1), ..Bvh::default() };
        if !order.is_empty() {
            bvh.split(&bounds, &classes, &mut order, &mut slots);
            bvh.widen(0);
            // Coordinates and distances up to m carry f32 rounding errors of a few m·2⁻²⁴
            // (p's rounding, the subtractions, squares, sum and root): 2⁻¹⁸·m is ample.
            let m = bvh.nodes[0].lo.abs().max(bvh.nodes[0].hi.abs()).max_element() as f64 * 2.0;
            bvh.slack = m * 2f64.powi(-18);
        }
        bvh.nodes = Vec::new();
        bvh
    }

    /// Children of binary node n: left (next) and right.
    fn children(&self, n: usize) -> [usize; 2] {
        [n + 1, self.nodes[n].first as usize]
    }

    /// Collapses the binary subtree at inner node `n` into wide nodes: its children, with the
    /// biggest inner ones replaced by their own children until there are four. Returns the
    /// wide node's index.
    fn widen(&mut self, n: usize) -> u32 {
        // A root that is a leaf node (few leaves) becomes the only child of a wide root.
        let mut kids: Vec<usize> = if self.nodes[n].count > 0 { vec![n] } else { self.children(n).to_vec() };
        while kids.len() < 4 {
            let volume = |i: usize| {
                let node = &self.nodes[i];
                (node.hi - node.lo).as_dvec3().element_product()
            };
            let inner = kids.iter().enumerate().filter(|&(_, &k)| self.nodes[k].count == 0);
            let Some((at, _)) = inner.max_by(|a, b| volume(*a.1).total_cmp(&volume(*b.1))) else {
                break;
            };
            let k = kids.remove(at);
            let [l, r] = self.children(k);
            kids.insert(at, r);
            kids.insert(at, l);
        }
        let index = self.wide.len();
        self.wide.push(Wide {
            lo: [[f32::INFINITY; 4]; 3],
            hi: [[f32::NEG_INFINITY; 4]; 3],
            child: [0; 4],
            count: [0; 4],
        });
        for (slot, &k) in kids.iter().enumerate() {
            let node = self.nodes[k].clone();
            for axis in 0..3 {
                self.wide[index].lo[axis][slot] = node.lo[axis];
                self.wide[index].hi[axis][slot] = node.hi[axis];
            }
            if node.count > 0 {
                self.wide[index].child[slot] = node.first;
                self.wide[index].count[slot] = node.count;
            } else {
                let child = self.widen(k);
                self.wide[index].child[slot] = child;
            }
        }
        index as u32
    }

    fn split(
        &mut self,
        bounds: &[(DVec3, DVec3)],
        classes: &[u8],
        items: &mut [u32],
        slots: &mut [Option<Leaf>],
    ) -> usize {
        let (lo, hi) = items.iter().fold((DVec3::INFINITY, DVec3::NEG_INFINITY), |(lo, hi), &i| {
            (lo.min(bounds[i as usize].0), hi.max(bounds[i as usize].1))
        });
        let index = self.nodes.len();
        self.nodes.push(Node { lo: round_down(lo), hi: round_up(hi), first: 0, count: 0 });
        let class = classes[items[0] as usize];
        let uniform = items.iter().all(|&i| classes[i as usize] == class);
        if items.len() <= LEAF && uniform {
            let first = self.store(items, slots);
            self.nodes[index].first = first;
            self.nodes[index].count = items.len() as u32 | (class as u32) << 16;
            return index;
        }
        let mid = if items.len() <= LEAF {
            // Mixed kinds: split off the smallest kind.
            items.sort_unstable_by_key(|&i| (classes[i as usize], i));
            let smallest = classes[items[0] as usize];
            items.iter().position(|&i| classes[i as usize] != smallest).expect("mixed classes")
        } else {
            // Split across the longest extent of the leaves' centres.
            let (clo, chi) = items.iter().fold((DVec3::INFINITY, DVec3::NEG_INFINITY), |(lo, hi), &i| {
                let c = bounds[i as usize].0 + bounds[i as usize].1;
                (lo.min(c), hi.max(c))
            });
            match binned_split(bounds, items, clo, chi) {
                Some(mid) => mid,
                None => {
                    let axis = (chi - clo).max_position();
                    let centre = |i: u32| bounds[i as usize].0[axis] + bounds[i as usize].1[axis];
                    let mid = items.len() / 2;
                    items.select_nth_unstable_by(mid, |&x, &y| {
                        centre(x).total_cmp(&centre(y)).then(x.cmp(&y))
                    });
                    mid
                }
            }
        };
        let (left, right) = items.split_at_mut(mid);
        self.split(bounds, classes, left, slots);
        let right_index = self.split(bounds, classes, right, slots);
        self.nodes[index].first = right_index as u32;
        index
    }

    /// Moves the leaves `items` (of one class) to the end of their kind's array; returns where
    /// they start.
    fn store(&mut self, items: &[u32], slots: &mut [Option<Leaf>]) -> u32 {
        let mut first = None;
        for &i in items {
            let at = match slots[i as usize].take().expect("each leaf once") {
                Leaf::Sphere(s, t) => {
                    self.sphere_types.push(t as u8);
                    push(&mut self.spheres, s)
                }
                Leaf::Sweep(s, t) => {
                    self.sweep_types.push(t as u8);
                    push(&mut self.sweeps, s)
                }
                Leaf::Water(w) => push(&mut self.water, w),
                Leaf::Chamber(c) => push(&mut self.chambers, c),
                Leaf::Capsule(c) => push(&mut self.capsules, c),
            };
            first.get_or_insert(at);
        }
        first.expect("a leaf node holds leaves") as u32
    }

    /// Number of leaves.
    pub fn len(&self) -> usize {
        self.spheres.len() + self.sweeps.len() + self.water.len() + self.chambers.len() + self.capsules.len()
    }

    /// min(limit, min over leaves of their value at p).
    pub fn min_value(&self, p: DVec3, limit: f64, ctx: &Context) -> f64 {
        let mut best = limit;
        if self.wide.is_empty() {
            return best;
        }
        // (child, count, box distance): count 0 for a wide node.
        let p32 = p.as_vec3();
        let mut stack = [(0u32, 0u32, 0.0f64); 128];
        stack[0] = (0, 0, f64::NEG_INFINITY);
        let mut top = 1;
        while top > 0 {
            top -= 1;
            let (child, count, d) = stack[top];
            // Every leaf's value is at least its box's signed distance, which is at least the
            // node's (negative inside: a node holding p is skipped once best is deeper).
            if d >= best {
                continue;
            }
            if count > 0 {
                best = self.leaf_min(child, count, p, best, ctx);
                continue;
            }
            let node = &self.wide[child as usize];
            let near = self.children_distances(node, p32);
            // Push the farthest first, so that the nearest is visited first and the others are
            // more often pruned.
            for (d, i) in near {
                if d < best {
                    stack[top] = (node.child[i], node.count[i], d);
                    top += 1;
                }
            }
        }
        best
    }

    /// Lower bounds of the signed distances from p to the four children's boxes, farthest
    /// first. Computed four at a time in f32 from `p32` (p rounded) and lowered by
    /// `self.slack`, which exceeds the rounding error, so they never exceed the exact
    /// distances and pruning by them stays exact.
    fn children_distances(&self, node: &Wide, p32: Vec3) -> [(f64, usize); 4] {
        let axis = |a: usize, v: f32| {
            (Vec4::from_array(node.lo[a]) - Vec4::splat(v)).max(Vec4::splat(v) - Vec4::from_array(node.hi[a]))
        };
        let (dx, dy, dz) = (axis(0, p32.x), axis(1, p32.y), axis(2, p32.z));
        let (ox, oy, oz) = (dx.max(Vec4::ZERO), dy.max(Vec4::ZERO), dz.max(Vec4::ZERO));
        // The root and the sum in f32 too (one sqrtps): their rounding errors are among those
        // the slack covers.
        let d = ((ox * ox + oy * oy + oz * oz).sqrt() + dx.max(dy).max(dz).min(Vec4::ZERO)).to_array();
        // Sorted farthest first without branches (their outcome is random, so they were
        // mispredicted): each distance's f32 bits mapped to an order-preserving integer, the
        // slot in the two low bits, and a sorting network of max/min.
        let key = |i: usize| {
            let b = d[i].to_bits();
            let ordered = if b >> 31 == 1 { !b } else { b | 1 << 31 };
            (ordered as u64) << 2 | i as u64
        };
        let mut k = [key(0), key(1), key(2), key(3)];
        let order = |k: &mut [u64; 4], a: usize, b: usize| {
            let (x, y) = (k[a], k[b]);
            k[a] = x.max(y);
            k[b] = x.min(y);
        };
        order(&mut k, 0, 1);
        order(&mut k, 2, 3);
        order(&mut k, 0, 2);
        order(&mut k, 1, 3);
        order(&mut k, 1, 2);
        k.map(|k| {
            let b = (k >> 2) as u32;
            let bits = if b >> 31 == 1 { b & !(1 << 31) } else { !b };
            (f32::from_bits(bits) as f64 - self.slack, (k & 3) as usize)
        })
    }

    /// The minimum of `best` and the values of a leaf node's leaves.
    fn leaf_min(&self, first: u32, count: u32, p: DVec3, mut best: f64, ctx: &Context) -> f64 {
        let kind = (count >> 16) as u8;
        let range = first as usize..first as usize + (count & 0xffff) as usize;
        match kind {
            SPHERE => {
                for (s, &t) in self.spheres[range.clone()].iter().zip(&self.sphere_types[range]) {
                    best = best.min(sphere_value(p, s, ctx.amp(t, s[3]), best, ctx));
                }
            }
            SWEEP => {
                // Nearest first by a cheap lower bound, so that the exact sections are only
                // computed for sweeps that can still lower the minimum.
                let (sweeps, types) = (&self.sweeps[range.clone()], &self.sweep_types[range]);
                let amplitude = |k: usize| ctx.amp(types[k], sweeps[k].extent);
                let mut order = [(0.0f64, 0usize); LEAF];
                for (k, s) in sweeps.iter().enumerate() {
                    order[k] = (sweep_floor(p, s, amplitude(k), ctx), k);
                }
                let order = &mut order[..sweeps.len()];
                order.sort_unstable_by(|x, y| x.0.total_cmp(&y.0).then(x.1.cmp(&y.1)));
                for &(floor, k) in order.iter() {
                    if floor >= best {
                        break;
                    }
                    best = best.min(sweep_value(p, &sweeps[k], amplitude(k), best, ctx));
                }
            }
            WATER => {
                for w in &self.water[range] {
                    best = best.min(water_value(p, w, best, ctx));
                }
            }
            CHAMBER => {
                for c in &self.chambers[range] {
                    best = best.min(chamber_value(p, c, best, ctx));
                }
            }
            CAPSULE => {
                for c in &self.capsules[range] {
                    best = best.min(capsule_value(p, c));
                }
            }
            _ => unreachable!("leaf kinds are built by Leaf::kind"),
        }
        best
    }

    /// Appends to `out` the leaf nodes whose boxes come closer than `margin` to the box
    /// [lo, hi], and of the capsules' leaf nodes the single capsules whose own boxes do: every
    /// leaf whose value can be below `margin` somewhere in that box (a value is at least the
    /// distance to its box and to its leaf node's, at least the distance between the boxes).
    /// For p in the box and limit ≤ margin, [`Bvh::min_value_among`] over them equals
    /// [`Bvh::min_value`] bit for bit: both are min(limit, the exact values below it), whatever
    /// the order of the visits. The mesher gathers once per brick and evaluates its points
    /// against the short list instead of walking the hierarchy at every point.
    pub fn near_box(&self, lo: DVec3, hi: DVec3, margin: f64, out: &mut Vec<Candidate>) {
        if self.wide.is_empty() {
            return;
        }
        // The f32 boxes are rounded outwards, so the gap from them is never too large.
        let gap = |a: DVec3, b: DVec3| (a - hi).max(lo - b).max(DVec3::ZERO).length();
        // Once per brick, not per point: a vector, so no tree depth can overflow it.
        let mut stack: Vec<u32> = Vec::with_capacity(128);
        stack.push(0);
        while let Some(at) = stack.pop() {
            let node = &self.wide[at as usize];
            for slot in 0..4 {
                let a = DVec3::new(node.lo[0][slot] as f64, node.lo[1][slot] as f64, node.lo[2][slot] as f64);
                let b = DVec3::new(node.hi[0][slot] as f64, node.hi[1][slot] as f64, node.hi[2][slot] as f64);
                // Empty slots have an inverted (infinite) box and never pass.
                if !(a.cmple(b).all() && gap(a, b) < margin) {
                    continue;
                }
                match node.count[slot] {
                    0 => stack.push(node.child[slot]),
                    count if (count >> 16) as u8 == CAPSULE => {
                        // A leaf node's capsules follow a conduit for tens of metres: only the
                        // few whose own boxes come close are kept, each as its own candidate.
                        let first = node.child[slot] as usize;
                        for (k, c) in
                            self.capsules[first..first + (count & 0xffff) as usize].iter().enumerate()
                        {
                            let (lo, hi) = c.bounds();
                            if gap(lo, hi) < margin {
                                let (first, count) = ((first + k) as u32, ONE_CAPSULE);
                                out.push(Candidate { first, count, lo, hi });
                            }
                        }
                    }
                    count => out.push(Candidate { first: node.child[slot], count, lo: a, hi: b }),
                }
            }
        }
        // Nearest to the box's centre first, so that the running minimum drops early and the
        // farther leaf nodes stop at their box test.
        let centre = (lo + hi) * 0.5;
        let key = |c: &Candidate| signed_box_distance(c.lo, c.hi, centre);
        out.sort_by(|x, y| key(x).total_cmp(&key(y)).then(x.count.cmp(&y.count)).then(x.first.cmp(&y.first)));
    }

    /// min(`limit`, the smallest gap between the box [lo, hi] and the boxes of the leaf nodes
    /// `among`): a lower bound of [`Bvh::min_value_among`] at every point of that box with that
    /// limit, since a leaf's value is at least the distance to its leaf node's box. Positive
    /// exactly when no leaf node's box meets the box (the f32 boxes are rounded outwards and
    /// the subtractions round monotonically, so a positive gap is never a rounding artefact).
    pub fn gap_among(among: &[Candidate], lo: DVec3, hi: DVec3, limit: f64) -> f64 {
        among.iter().map(|c| (c.lo - hi).max(lo - c.hi).max(DVec3::ZERO).length()).fold(limit, f64::min)
    }

    /// min(limit, min over the leaves of the leaf nodes `among` of their value at p). A leaf
    /// node whose box is no closer than the running minimum is skipped without being opened.
    pub fn min_value_among(&self, among: &[Candidate], p: DVec3, limit: f64, ctx: &Context) -> f64 {
        let mut best = limit;
        for c in among {
            // The largest gap along one axis is at most the box's distance: a cheap first test.
            if (c.lo - p).max(p - c.hi).max_element() >= best {
                continue;
            }
            if c.count == ONE_CAPSULE {
                // Its value already is at least its box's distance.
                best = best.min(capsule_value(p, &self.capsules[c.first as usize]));
            } else if signed_box_distance(c.lo, c.hi, p) < best {
                best = self.leaf_min(c.first, c.count, p, best, ctx);
            }
        }
        best
    }

    /// min over every leaf, without the hierarchy: the reference its pruning is tested against.
    pub fn min_without_bvh(&self, p: DVec3, limit: f64, ctx: &Context) -> f64 {
        let mut best = limit;
        let ranges = self.wide.iter().flat_map(|w| w.child.iter().zip(&w.count)).filter(|(_, c)| **c > 0);
        for (&first, &count) in ranges {
            let kind = (count >> 16) as u8;
            let range = first as usize..first as usize + (count & 0xffff) as usize;
            let inf = f64::INFINITY;
            let values: Vec<f64> = match kind {
                SPHERE => (range.clone())
                    .map(|k| {
                        let s = &self.spheres[k];
                        sphere_value(p, s, ctx.amp(self.sphere_types[k], s[3]), inf, ctx)
                    })
                    .collect(),
                SWEEP => (range.clone())
                    .map(|k| {
                        let s = &self.sweeps[k];
                        sweep_value(p, s, ctx.amp(self.sweep_types[k], s.extent), inf, ctx)
                    })
                    .collect(),
                WATER => self.water[range].iter().map(|w| water_value(p, w, inf, ctx)).collect(),
                CHAMBER => self.chambers[range].iter().map(|c| chamber_value(p, c, inf, ctx)).collect(),
                _ => self.capsules[range].iter().map(|c| capsule_value(p, c)).collect(),
            };
            best = values.into_iter().fold(best, f64::min);
        }
        best
    }

    /// Bytes held by the tree and its leaves (not the shared sweep table).
    pub fn memory(&self) -> usize {
        use std::mem::size_of;
        self.wide.len() * size_of::<Wide>()
            + self.spheres.len() * (size_of::<[f32; 4]>() + 1)
            + self.sweeps.len() * (size_of::<SweepLeaf>() + 1)
            + self.water.len() * size_of::<WaterLeaf>()
            + self.chambers.len() * size_of::<Chamber>()
            + self.capsules.len() * size_of::<Capsule>()
    }
}

/// Bins of the surface-area split.
const BINS: usize = 16;

/// The surface-area heuristic over `BINS` bins of the centres (lo..hi, doubled) on each axis:
/// the split minimising area(left)·n(left) + area(right)·n(right), so that sibling boxes overlap
/// less than with a median split. Partitions `items` and returns the split position; `None`
/// when every centre falls in one bin.
fn binned_split(bounds: &[(DVec3, DVec3)], items: &mut [u32], lo: DVec3, hi: DVec3) -> Option<usize> {
    let area = |(l, h): (DVec3, DVec3)| {
        let e = (h - l).max(DVec3::ZERO);
        e.x * e.y + e.y * e.z + e.z * e.x
    };
    let empty = (DVec3::INFINITY, DVec3::NEG_INFINITY);
    let join = |a: (DVec3, DVec3), b: (DVec3, DVec3)| (a.0.min(b.0), a.1.max(b.1));
    let bin = |i: u32, axis: usize| {
        let c = bounds[i as usize].0[axis] + bounds[i as usize].1[axis];
        let t = (c - lo[axis]) / (hi[axis] - lo[axis]);
        ((t * BINS as f64) as usize).min(BINS - 1)
    };
    let mut best: Option<(f64, usize, usize)> = None;
    for axis in 0..3 {
        if hi[axis] <= lo[axis] {
            continue;
        }
        let mut boxes = [empty; BINS];
        let mut counts = [0usize; BINS];
        for &i in items.iter() {
            let b = bin(i, axis);
            boxes[b] = join(boxes[b], bounds[i as usize]);
            counts[b] += 1;
        }
        // Costs of splitting before bin k, from the right.
        let mut right = [0.0; BINS];
        let (mut acc, mut n) = (empty, 0);
        for k in (1..BINS).rev() {
            acc = join(acc, boxes[k]);
            n += counts[k];
            right[k] = if n > 0 { area(acc) * n as f64 } else { 0.0 };
        }
        let (mut acc, mut n) = (empty, 0);
        for k in 1..BINS {
            acc = join(acc, boxes[k - 1]);
            n += counts[k - 1];
            if n == 0 || n == items.len() {
                continue;
            }
            let cost = area(acc) * n as f64 + right[k];
            if best.is_none_or(|(c, _, _)| cost < c) {
                best = Some((cost, axis, k));
            }
        }
    }
    let (_, axis, k) = best?;
    // Stable partition: the order inside each side stays the input's.
    let (left, right): (Vec<u32>, Vec<u32>) = items.iter().partition(|&&i| bin(i, axis) < k);
    let mid = left.len();
    items[..mid].copy_from_slice(&left);
    items[mid..].copy_from_slice(&right);
    Some(mid)
}

fn push<T>(v: &mut Vec<T>, item: T) -> usize {
    v.push(item);
    v.len() - 1
}

fn round_down(v: DVec3) -> Vec3 {
    let f = v.as_vec3();
    Vec3::new(down(f.x, v.x), down(f.y, v.y), down(f.z, v.z))
}

fn round_up(v: DVec3) -> Vec3 {
    -round_down(-v)
}

fn down(f: f32, exact: f64) -> f32 {
    if f as f64 > exact { f.next_down() } else { f }
}
