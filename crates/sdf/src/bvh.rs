//! A bounding-volume hierarchy over the capsules, so that evaluating the field at a point
//! visits only the capsules that can be the nearest.

use glam::DVec3;

use crate::Capsule;

/// Capsules per leaf.
const LEAF: usize = 4;

#[derive(Debug, Clone)]
struct Node {
    lo: DVec3,
    hi: DVec3,
    /// Leaf: capsule range in `order`; inner: `first` is the right child (left is next).
    first: u32,
    count: u32,
}

/// A median-split BVH; capsules are reordered in `order`.
#[derive(Debug, Clone, Default)]
pub struct Bvh {
    nodes: Vec<Node>,
    order: Vec<u32>,
}

impl Bvh {
    pub fn build(capsules: &[Capsule]) -> Self {
        let bounds: Vec<(DVec3, DVec3)> = capsules.iter().map(Capsule::bounds).collect();
        let mut bvh = Bvh { nodes: Vec::new(), order: (0..capsules.len() as u32).collect() };
        if !capsules.is_empty() {
            let mut order = std::mem::take(&mut bvh.order);
            bvh.split(&bounds, &mut order, 0);
            bvh.order = order;
        }
        bvh
    }

    fn split(&mut self, bounds: &[(DVec3, DVec3)], items: &mut [u32], offset: usize) -> usize {
        let (lo, hi) = items.iter().fold((DVec3::INFINITY, DVec3::NEG_INFINITY), |(lo, hi), &i| {
            (lo.min(bounds[i as usize].0), hi.max(bounds[i as usize].1))
        });
        let index = self.nodes.len();
        self.nodes.push(Node { lo, hi, first: offset as u32, count: items.len() as u32 });
        if items.len() <= LEAF {
            return index;
        }
        let axis = (hi - lo).max_position();
        let centre = |i: u32| (bounds[i as usize].0[axis] + bounds[i as usize].1[axis], i);
        items.sort_unstable_by(|&x, &y| centre(x).0.total_cmp(&centre(y).0).then(x.cmp(&y)));
        let mid = items.len() / 2;
        let (left, right) = items.split_at_mut(mid);
        self.split(bounds, left, offset);
        let right_index = self.split(bounds, right, offset + mid);
        self.nodes[index].first = right_index as u32;
        self.nodes[index].count = 0;
        index
    }

    /// min(limit, min over capsules of their signed distance at p): capsules that cannot go
    /// below `limit` are skipped.
    pub fn min_distance(&self, capsules: &[Capsule], p: DVec3, limit: f64) -> f64 {
        let mut best = limit;
        if self.nodes.is_empty() {
            return best;
        }
        let mut stack = vec![0usize];
        while let Some(n) = stack.pop() {
            let node = &self.nodes[n];
            if box_distance(node.lo, node.hi, p) >= best {
                continue;
            }
            if node.count > 0 {
                let range = node.first as usize..(node.first + node.count) as usize;
                for &i in &self.order[range] {
                    best = best.min(capsules[i as usize].distance(p));
                }
            } else {
                stack.push(node.first as usize);
                stack.push(n + 1);
            }
        }
        best
    }
}

/// Distance from p to the box (0 inside); a lower bound of the distance to anything in it.
fn box_distance(lo: DVec3, hi: DVec3, p: DVec3) -> f64 {
    (lo - p).max(p - hi).max(DVec3::ZERO).length()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn agrees_with_brute_force() {
        let capsules: Vec<Capsule> = (0..50)
            .map(|i| {
                let x = (i * 37 % 50) as f64 * 4.0;
                let y = (i * 11 % 50) as f64 * 4.0;
                Capsule { a: [x, y, 0.0], b: [x + 5.0, y - 3.0, 2.0], radius: 1.0 + (i % 3) as f64 }
            })
            .collect();
        let bvh = Bvh::build(&capsules);
        for k in 0..200 {
            let p = DVec3::new((k * 13 % 211) as f64, (k * 7 % 199) as f64, (k % 9) as f64 - 4.0);
            let brute = capsules.iter().map(|c| c.distance(p)).fold(f64::INFINITY, f64::min);
            assert_eq!(bvh.min_distance(&capsules, p, f64::INFINITY), brute);
            assert_eq!(bvh.min_distance(&capsules, p, 0.5), brute.min(0.5));
        }
    }
}
