//! Meshing a model: the carved terrain and the cave alone, each polygonized and cleaned, and
//! the water in the conduits.

use glam::DVec3;

use karst_sdf::CarvedTerrain;

use crate::Mesh;
use crate::cleanup::{Solid, clean};
use crate::polygonize::polygonize;
use crate::simplify::simplify;
use crate::volume::{Cave, Water};

/// The three surfaces of `field` at `cell_size`; `anchors` (sinks and springs) keep the air
/// around them even when it is sealed in rock.
pub fn build(field: &CarvedTerrain, cell_size: f64, anchors: &[DVec3]) -> Mesh {
    let mut terrain = polygonize(field, cell_size);
    clean(&mut terrain, Solid::Rock, field.model(), anchors, cell_size);
    let mut cave = polygonize(&Cave(field), cell_size);
    clean(&mut cave, Solid::Cave, field.model(), anchors, cell_size);
    let water = polygonize(&Water(field), cell_size);
    Mesh { cell_size, terrain, cave, water }
}

/// [`build`], then each surface simplified to at most `target_triangles` (0: not simplified).
pub fn build_simplified(
    field: &CarvedTerrain,
    cell_size: f64,
    anchors: &[DVec3],
    target_triangles: u64,
) -> Mesh {
    let mut mesh = build(field, cell_size, anchors);
    if target_triangles > 0 {
        for surface in [&mut mesh.terrain, &mut mesh.cave, &mut mesh.water] {
            simplify(surface, target_triangles as usize);
        }
    }
    mesh
}
