//! Simplification to a target triangle count by edge collapse, keeping the surface closed,
//! 2-manifold, oriented and free of degenerate triangles.
//!
//! The shortest edge is collapsed first, to its midpoint, one at a time and with ties broken
//! by vertex ids, so the result is deterministic. A collapse of a–b is refused when it would
//! break a promise: a and b must share exactly the two neighbours opposite the edge (the link
//! condition, which keeps the surface a 2-manifold), the merged vertex must keep three
//! neighbours (no flattened tetrahedron), and no surviving triangle around it may flip or
//! lose its area. Shortest-first with midpoints removes the lattice's small sliver triangles
//! first and moves the surface by at most half an edge per collapse.

use std::cmp::Reverse;
use std::collections::BinaryHeap;

use glam::DVec3;

use crate::payload::TriMesh;

/// Collapses edges until `surface` has at most `target` triangles or no collapse is legal.
pub fn simplify(surface: &mut TriMesh, target: usize) {
    let mut mesh = Working::new(surface);
    let mut queue = BinaryHeap::new();
    for t in &surface.triangles {
        for e in 0..3 {
            let (a, b) = (t[e], t[(e + 1) % 3]);
            if a < b {
                queue.push(Reverse((Length(mesh.length(a, b)), a, b)));
            }
        }
    }
    let mut alive = surface.triangles.len();
    while alive > target {
        let Some(Reverse((Length(length), a, b))) = queue.pop() else { break };
        if !mesh.alive[a as usize] || !mesh.alive[b as usize] || mesh.length(a, b) != length {
            continue;
        }
        if let Some(removed) = mesh.collapse(a, b) {
            alive -= removed;
            for &n in &mesh.neighbours(a) {
                queue.push(Reverse((Length(mesh.length(a.min(n), a.max(n))), a.min(n), a.max(n))));
            }
        }
    }
    mesh.write_back(surface);
}

/// An edge length ordered totally (lengths are finite).
#[derive(Debug, Clone, Copy, PartialEq)]
struct Length(f64);

impl Eq for Length {}

impl PartialOrd for Length {
    fn partial_cmp(&self, other: &Self) -> Option<std::cmp::Ordering> {
        Some(self.cmp(other))
    }
}

impl Ord for Length {
    fn cmp(&self, other: &Self) -> std::cmp::Ordering {
        self.0.total_cmp(&other.0)
    }
}

/// The mesh being simplified: positions, triangles and, per vertex, its triangles.
struct Working {
    positions: Vec<DVec3>,
    triangles: Vec<Option<[u32; 3]>>,
    around: Vec<Vec<u32>>,
    alive: Vec<bool>,
}

impl Working {
    fn new(surface: &TriMesh) -> Self {
        let mut around = vec![Vec::new(); surface.vertices.len()];
        for (i, t) in surface.triangles.iter().enumerate() {
            for &v in t {
                around[v as usize].push(i as u32);
            }
        }
        Working {
            positions: (0..surface.vertices.len() as u32).map(|v| surface.position(v)).collect(),
            triangles: surface.triangles.iter().map(|&t| Some(t)).collect(),
            alive: around.iter().map(|a| !a.is_empty()).collect(),
            around,
        }
    }

    fn length(&self, a: u32, b: u32) -> f64 {
        self.positions[a as usize].distance(self.positions[b as usize])
    }

    /// Vertices sharing a triangle with v, sorted.
    fn neighbours(&self, v: u32) -> Vec<u32> {
        let mut n: Vec<u32> = self.around[v as usize]
            .iter()
            .filter_map(|&t| self.triangles[t as usize])
            .flatten()
            .filter(|&u| u != v)
            .collect();
        n.sort_unstable();
        n.dedup();
        n
    }

    /// Merges b into a at their midpoint when legal; returns the triangles removed.
    fn collapse(&mut self, a: u32, b: u32) -> Option<usize> {
        let (na, nb) = (self.neighbours(a), self.neighbours(b));
        if na.binary_search(&b).is_err() {
            return None;
        }
        let common = na.iter().filter(|v| nb.binary_search(v).is_ok()).count();
        let merged =
            na.iter().chain(&nb).filter(|&&v| v != a && v != b).collect::<std::collections::BTreeSet<_>>();
        if common != 2 || merged.len() < 3 {
            return None;
        }
        let midpoint = (self.positions[a as usize] + self.positions[b as usize]) * 0.5;
        let moved = |v: u32| if v == a || v == b { midpoint } else { self.positions[v as usize] };
        let shared = |t: &[u32; 3]| t.contains(&a) && t.contains(&b);
        for &ti in self.around[a as usize].iter().chain(&self.around[b as usize]) {
            let Some(t) = self.triangles[ti as usize] else { continue };
            if shared(&t) {
                continue;
            }
            let old = normal(t.map(|v| self.positions[v as usize]));
            let new = normal(t.map(moved));
            if new.dot(old) <= 0.0 || new.length_squared() <= 1e-12 * old.length_squared() {
                return None;
            }
        }
        let mut removed = 0;
        let from_b = std::mem::take(&mut self.around[b as usize]);
        for &ti in &from_b {
            let Some(t) = self.triangles[ti as usize] else { continue };
            if shared(&t) {
                self.triangles[ti as usize] = None;
                removed += 1;
            } else {
                self.triangles[ti as usize] = Some(t.map(|v| if v == b { a } else { v }));
                self.around[a as usize].push(ti);
            }
        }
        self.around[a as usize].retain(|&ti| self.triangles[ti as usize].is_some());
        self.around[a as usize].sort_unstable();
        self.around[a as usize].dedup();
        self.positions[a as usize] = midpoint;
        self.alive[b as usize] = false;
        Some(removed)
    }

    /// Writes the surviving triangles and vertices back, in their order.
    fn write_back(self, surface: &mut TriMesh) {
        let mut renumber = vec![u32::MAX; self.positions.len()];
        let mut vertices = Vec::new();
        let mut triangles = Vec::new();
        for t in self.triangles.into_iter().flatten() {
            triangles.push(t.map(|v| {
                if renumber[v as usize] == u32::MAX {
                    renumber[v as usize] = vertices.len() as u32;
                    vertices.push(self.positions[v as usize].as_vec3().to_array());
                }
                renumber[v as usize]
            }));
        }
        surface.vertices = vertices;
        surface.triangles = triangles;
    }
}

fn normal([a, b, c]: [DVec3; 3]) -> DVec3 {
    (b - a).cross(c - a)
}
