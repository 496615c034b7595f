//! Marching cubes on the rectilinear terrain lattice ([`crate::terrain_lattice`]) by the
//! regular polygonizer, through a change of coordinates.
//!
//! Lattice space u has unit cells: u = i is plane i of an axis, and between two planes the map
//! to the world, φ, is affine along each axis. The polygonizer meshes g(u) = f(φ(u)) / w, w the
//! widest world cell: φ stretches no distance by more than w, so g is 1-Lipschitz in u as the
//! polygonizer's octree and lazy corners require. g has the sign of f, and the ratio of two
//! values, where a vertex goes on an edge, is f's: a vertex at u maps to the vertex marching
//! cubes would put on the world lattice's edge, and a loop's centre (a mean of vertices of one
//! cell, where φ is affine) to the world mean. The polygonizer's vertices are mapped to the
//! world as they are handed over ([`ToWorld`]).

use glam::DVec3;

use crate::sink::MeshSink;
use crate::terrain_lattice::TerrainLattice;
use crate::volume::Volume;

/// A solid seen in the lattice space of a [`TerrainLattice`].
pub struct Warped<'a, V> {
    solid: &'a V,
    lattice: &'a TerrainLattice,
    /// The widest world cell: g = f / widest.
    widest: f64,
}

impl<'a, V: Volume> Warped<'a, V> {
    pub fn new(solid: &'a V, lattice: &'a TerrainLattice) -> Self {
        Warped { solid, lattice, widest: lattice.widest() }
    }

    /// φ(u): the world point of lattice-space point `u`.
    pub fn to_world(&self, u: DVec3) -> DVec3 {
        self.lattice.to_world(u)
    }
}

impl<V: Volume> Volume for Warped<'_, V> {
    fn eval(&self, u: DVec3) -> f64 {
        self.solid.eval(self.to_world(u)) / self.widest
    }

    /// In the world the reach is `reach` · w: exact where |g| < reach, at least reach beyond.
    fn eval_within(&self, u: DVec3, reach: f64) -> f64 {
        self.solid.eval_within(self.to_world(u), reach * self.widest) / self.widest
    }

    fn eval_block(&self, lo: DVec3, hi: DVec3, reach: f64, points: &[DVec3], out: &mut Vec<f64>) {
        let world: Vec<DVec3> = points.iter().map(|&u| self.to_world(u)).collect();
        let from = out.len();
        self.solid.eval_block(self.to_world(lo), self.to_world(hi), reach * self.widest, &world, out);
        for v in &mut out[from..] {
            *v /= self.widest;
        }
    }

    /// The world box's bound, which is positive exactly when the surface cannot cross it.
    fn bound(&self, lo: DVec3, hi: DVec3) -> f64 {
        self.solid.bound(self.to_world(lo), self.to_world(hi)) / self.widest
    }

    fn bounds(&self, lo: DVec3, hi: DVec3, boxes: &[(DVec3, DVec3)], out: &mut [f64]) {
        let world: Vec<(DVec3, DVec3)> =
            boxes.iter().map(|&(l, h)| (self.to_world(l), self.to_world(h))).collect();
        self.solid.bounds(self.to_world(lo), self.to_world(hi), &world, out);
        for b in out.iter_mut() {
            *b /= self.widest;
        }
    }

    /// Planes 1 to n − 1.5: the polygonizer's lattice around it (one cell more on each side,
    /// rounded up) has the unit planes 0 to n.
    fn extent(&self) -> (DVec3, DVec3) {
        let n = self.lattice.cells().map(|c| c as f64 - 1.5);
        (DVec3::ONE, DVec3::from_array(n))
    }
}

/// Hands a mesh of lattice space over to `sink` with its vertices mapped to the world.
pub struct ToWorld<'a, 's, V, S> {
    pub warp: &'a Warped<'a, V>,
    pub sink: &'s mut S,
}

impl<V: Volume, S: MeshSink> MeshSink for ToWorld<'_, '_, V, S> {
    type Error = S::Error;

    fn vertices(&mut self, vertices: &[[f32; 3]]) -> Result<(), S::Error> {
        let world: Vec<[f32; 3]> = vertices
            .iter()
            .map(|&u| self.warp.to_world(glam::Vec3::from_array(u).as_dvec3()).as_vec3().to_array())
            .collect();
        self.sink.vertices(&world)
    }

    fn triangles(&mut self, triangles: &[[u32; 3]]) -> Result<(), S::Error> {
        self.sink.triangles(triangles)
    }
}

/// `solid` polygonized into `sink` on `lattice`, its vertices mapped to the world; returns the
/// field evaluations.
pub fn polygonize_warped_into<V: Volume, S: MeshSink>(
    solid: &V,
    lattice: &TerrainLattice,
    sink: &mut S,
) -> Result<u64, S::Error> {
    let warp = Warped::new(solid, lattice);
    crate::polygonize::polygonize_into(&warp, 1.0, &mut ToWorld { warp: &warp, sink })
}
