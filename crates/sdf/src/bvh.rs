//! A bounding-volume hierarchy over the leaves, so that evaluating the union at a point visits
//! only the leaves that can be below the current minimum, and so that a whole box of space can
//! be bounded at once.
//!
//! Median split on the longest axis; leaves are reordered into tree order (no index array).
//! Node boxes are f32, rounded outwards, to keep the tree at 32 bytes per node.

use glam::{DVec3, Vec3};

use crate::primitive::{Context, Primitive, signed_box_distance};

/// Leaves per BVH leaf node.
const LEAF: usize = 8;

#[derive(Debug, Clone)]
struct Node {
    lo: Vec3,
    hi: Vec3,
    /// Leaf: first primitive; inner: the right child (the left one is next).
    first: u32,
    /// Primitives of a leaf node; 0 for an inner node.
    count: u32,
}

/// A primitive gathered by [`Bvh::near_box`], with its box.
#[derive(Debug, Clone, Copy)]
pub struct Candidate {
    index: u32,
    lo: DVec3,
    hi: DVec3,
}

/// The hierarchy and its primitives, in tree order.
#[derive(Debug, Clone, Default)]
pub struct Bvh {
    nodes: Vec<Node>,
    pub primitives: Vec<Primitive>,
}

impl Bvh {
    pub fn build(primitives: Vec<Primitive>) -> Self {
        let bounds: Vec<(DVec3, DVec3)> = primitives.iter().map(Primitive::bounds).collect();
        let mut order: Vec<u32> = (0..primitives.len() as u32).collect();
        let mut bvh =
            Bvh { nodes: Vec::with_capacity(2 * primitives.len() / LEAF + 1), primitives: Vec::new() };
        if !order.is_empty() {
            bvh.split(&bounds, &mut order, 0);
        }
        let mut slots: Vec<Option<Primitive>> = primitives.into_iter().map(Some).collect();
        bvh.primitives =
            order.iter().map(|&i| slots[i as usize].take().expect("each primitive once")).collect();
        bvh
    }

    fn split(&mut self, bounds: &[(DVec3, DVec3)], items: &mut [u32], offset: usize) -> usize {
        let (lo, hi) = items.iter().fold((DVec3::INFINITY, DVec3::NEG_INFINITY), |(lo, hi), &i| {
            (lo.min(bounds[i as usize].0), hi.max(bounds[i as usize].1))
        });
        let index = self.nodes.len();
        self.nodes.push(Node {
            lo: round_down(lo),
            hi: round_up(hi),
            first: offset as u32,
            count: items.len() as u32,
        });
        if items.len() <= LEAF {
            return index;
        }
        let axis = (hi - lo).max_position();
        let centre = |i: u32| bounds[i as usize].0[axis] + bounds[i as usize].1[axis];
        let mid = items.len() / 2;
        items.select_nth_unstable_by(mid, |&x, &y| centre(x).total_cmp(&centre(y)).then(x.cmp(&y)));
        let (left, right) = items.split_at_mut(mid);
        self.split(bounds, left, offset);
        let right_index = self.split(bounds, right, offset + mid);
        self.nodes[index].first = right_index as u32;
        self.nodes[index].count = 0;
        index
    }

    /// min(limit, min over primitives of their value at p).
    pub fn min_value(&self, p: DVec3, limit: f64, ctx: &Context) -> f64 {
        let mut best = limit;
        if self.nodes.is_empty() {
            return best;
        }
        let mut stack = [0u32; 64];
        let mut top = 1;
        while top > 0 {
            top -= 1;
            let n = stack[top] as usize;
            let node = &self.nodes[n];
            // Every leaf's value is at least its box's signed distance, which is at least the
            // node's (negative inside: a node holding p is skipped once best is deeper).
            if signed_box_distance(node.lo.as_dvec3(), node.hi.as_dvec3(), p) >= best {
                continue;
            }
            if node.count > 0 {
                let range = node.first as usize..(node.first + node.count) as usize;
                for prim in &self.primitives[range] {
                    best = best.min(prim.value(p, best, ctx));
                }
            } else {
                // Visit the nearer child first, so the farther one is more often pruned.
                let (l, r) = (n + 1, node.first as usize);
                let dl = signed_box_distance(self.nodes[l].lo.as_dvec3(), self.nodes[l].hi.as_dvec3(), p);
                let dr = signed_box_distance(self.nodes[r].lo.as_dvec3(), self.nodes[r].hi.as_dvec3(), p);
                let (near, far) = if dl <= dr { (l, r) } else { (r, l) };
                stack[top] = far as u32;
                stack[top + 1] = near as u32;
                top += 2;
            }
        }
        best
    }

    /// Appends to `out` (in tree order) the primitives whose boxes come closer than `margin` to
    /// the box [lo, hi]: every primitive whose value can be below `margin` somewhere in that
    /// box (a value is at least the distance to the primitive's box, at least the distance
    /// between the boxes). For p in the box and limit ≤ margin, [`Bvh::min_value_among`] over
    /// them equals [`Bvh::min_value`] bit for bit: both are min(limit, the exact values below
    /// it), whatever the order of the visits.
    pub fn near_box(&self, lo: DVec3, hi: DVec3, margin: f64, out: &mut Vec<Candidate>) {
        if self.nodes.is_empty() {
            return;
        }
        let gap = |a: DVec3, b: DVec3| (a - hi).max(lo - b).max(DVec3::ZERO).length();
        let mut stack = [0u32; 64];
        let mut top = 1;
        while top > 0 {
            top -= 1;
            let n = stack[top] as usize;
            let node = &self.nodes[n];
            if gap(node.lo.as_dvec3(), node.hi.as_dvec3()) >= margin {
                continue;
            }
            if node.count > 0 {
                for i in node.first..node.first + node.count {
                    let (a, b) = self.primitives[i as usize].bounds();
                    if gap(a, b) < margin {
                        out.push(Candidate { index: i, lo: a, hi: b });
                    }
                }
            } else {
                stack[top] = node.first;
                stack[top + 1] = (n + 1) as u32;
                top += 2;
            }
        }
        // Nearest to the box's centre first, so that the running minimum drops early and the
        // farther leaves stop at their box test.
        let centre = (lo + hi) * 0.5;
        let key = |c: &Candidate| signed_box_distance(c.lo, c.hi, centre);
        out.sort_by(|x, y| key(x).total_cmp(&key(y)).then(x.index.cmp(&y.index)));
    }

    /// min(limit, min over the primitives `among` of their value at p).
    /// A leaf's value is at least its box's signed distance, so leaves whose box is no closer
    /// than the running minimum are skipped without being evaluated.
    pub fn min_value_among(&self, among: &[Candidate], p: DVec3, limit: f64, ctx: &Context) -> f64 {
        let mut best = limit;
        for c in among {
            if signed_box_distance(c.lo, c.hi, p) < best {
                best = best.min(self.primitives[c.index as usize].value(p, best, ctx));
            }
        }
        best
    }

    /// Bytes held by the tree and its primitives (the sweeps' and chambers' boxed parts too).
    pub fn memory(&self) -> usize {
        use std::mem::size_of;
        let boxed: usize = self
            .primitives
            .iter()
            .map(|p| match p {
                Primitive::Sphere { .. } => 0,
                Primitive::Capsule(_) => size_of::<crate::Capsule>(),
                Primitive::Sweep(_) | Primitive::Water(_) => size_of::<(crate::sweep::Sweep, f64)>(),
                Primitive::Chamber(_) => size_of::<crate::chamber::Chamber>(),
            })
            .sum();
        self.nodes.len() * size_of::<Node>() + self.primitives.len() * size_of::<Primitive>() + boxed
    }
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
