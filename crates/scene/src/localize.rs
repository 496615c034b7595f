//! The scene's local frame: every coordinate moved by the domain's south-west-bottom corner.
//!
//! Real data comes in projected coordinates (Lambert-93, UTM: x and y in the hundreds of
//! thousands to millions of metres). At y ≈ 6.9e6 an f64 resolves 1e-9 m and an f32 only
//! 0.5 m, so comparisons decided by the rounding of world coordinates (a sample on a water
//! table, the dart a sampler picks, the mesher's f32 vertices) would change when a scene is
//! moved. A scene is therefore loaded, checked (messages in the file's world coordinates),
//! then localized: the domain's `min` becomes the origin, and the domain, terrain, surfaces,
//! layers, potential and no-karst volumes, grids, key points and hydro pools are moved by
//! −origin. Every stage computes in this frame; artifacts record the origin (f64) and exports
//! add it back. Noise terrains are defined in the local frame (x, y measured from the domain's
//! corner), so a moved scene carries its terrain with it.
//!
//! A scene whose domain starts at [0, 0, 0] is left untouched, bit for bit.

use std::sync::Arc;

use crate::view::Frame;
use karst_geology::field::{Bound, FieldNode};
use karst_geology::surface::Geometry;
use karst_geology::{Surface, Terrain};

use crate::Scene;

/// Moves every coordinate of `scene` into its local frame and records the origin.
pub(crate) fn localize(scene: &mut Scene) {
    let origin = scene.domain.min;
    scene.frame = Frame { origin, crs: scene.crs.clone() };
    if origin == [0.0; 3] {
        return;
    }
    let shift = Shift(origin);
    let by = origin.map(|o| -o);
    shift.point(&mut scene.domain.min);
    shift.point(&mut scene.domain.max);
    shift.terrain(&mut scene.terrain, by);
    let geology = &mut scene.geology;
    for s in geology.water_tables.iter_mut().chain(&mut geology.horizons).chain(&mut geology.faults) {
        shift.surface(s, by);
    }
    for layer in &mut geology.layers {
        shift.bound(&mut layer.top);
        shift.bound(&mut layer.bottom);
    }
    for node in geology.potential.iter_mut().chain(&mut geology.no_karst) {
        shift.node(node);
    }
    if let Some(grid) = &mut geology.grid {
        shift.point(&mut Arc::make_mut(&mut grid.values).origin);
    }
    if let Some(lithology) = &mut geology.lithology {
        if let Some(first) = &mut lithology.origin {
            shift.point(first);
        }
        Arc::make_mut(&mut lithology.grid).translate(by);
    }
    for k in &mut scene.keypoints {
        shift.point(&mut k.position);
    }
    for pool in &mut scene.hydro.pools {
        shift.point(&mut pool.at);
        for outlet in &mut pool.outlets {
            shift.point(&mut outlet.towards);
        }
    }
}

/// Subtracting the origin.
struct Shift([f64; 3]);

impl Shift {
    fn point(&self, p: &mut [f64; 3]) {
        for (c, o) in p.iter_mut().zip(self.0) {
            *c -= o;
        }
    }

    fn xy(&self, p: &mut [f64; 2]) {
        p[0] -= self.0[0];
        p[1] -= self.0[1];
    }

    fn z(&self, z: &mut f64) {
        *z -= self.0[2];
    }

    fn terrain(&self, terrain: &mut Terrain, by: [f64; 3]) {
        match terrain {
            Terrain::Plane { elevation, origin, .. } => {
                self.z(elevation);
                self.xy(origin);
            }
            Terrain::Heightfield { grid, .. } => Arc::make_mut(grid).translate(by),
            Terrain::Noise { elevation, anchor, .. } => {
                self.z(elevation);
                self.xy(anchor);
            }
        }
    }

    fn surface(&self, surface: &mut Surface, by: [f64; 3]) {
        match &mut surface.geometry {
            Geometry::Plane { elevation, origin, .. } => {
                self.z(elevation);
                self.xy(origin);
            }
            Geometry::Tin { mesh, .. } => Arc::make_mut(mesh).translate(by),
        }
    }

    fn bound(&self, bound: &mut Option<Bound>) {
        if let Some(Bound::Elevation(z)) = bound {
            self.z(z);
        }
    }

    fn node(&self, node: &mut FieldNode) {
        for p in [&mut node.centre, &mut node.min, &mut node.max].into_iter().flatten() {
            self.point(p);
        }
        self.bound(&mut node.top);
        self.bound(&mut node.bottom);
    }
}
