//! The carved terrain's surface: on the uniform lattice of the fine cell, or on its terrain
//! lattice ([`crate::terrain_lattice`]) through the change of coordinates of [`crate::warp`],
//! with the fine patches meshed on their own lattices and stitched in ([`crate::patches`]).

use crate::patches;
use crate::sink::MeshSink;
use crate::terrain_lattice::TerrainLattice;
use crate::warp::polygonize_warped_into;

/// The carved terrain of `field` polygonized into `sink` on its terrain lattice at fine cell
/// `cell` ([`TerrainLattice::of`]) with its fine patches stitched in ([`crate::patches`]), or
/// on the uniform lattice of `cell` when the terrain's coarse cell is not two fine ones;
/// returns the field evaluations. Should a patch's rim not close as its construction
/// promises, every cut becomes a fine window of whole slabs ([`TerrainLattice::slabs`]).
pub fn polygonize_terrain_into<S: MeshSink>(
    field: &karst_sdf::CarvedTerrain,
    cell: f64,
    sink: &mut S,
) -> Result<u64, S::Error> {
    let Some(lattice) = TerrainLattice::of(field, cell) else {
        return crate::polygonize::polygonize_into(field, cell, sink);
    };
    let lattice = if lattice.patches.is_empty() {
        lattice
    } else {
        match patches::polygonize_patched(field, &lattice) {
            Ok(mesh) => {
                sink.vertices(&mesh.vertices)?;
                sink.triangles(&mesh.triangles)?;
                return Ok(mesh.field_evaluations);
            }
            Err(patches::Unstitched) => TerrainLattice::slabs(field, cell).unwrap_or(lattice),
        }
    };
    polygonize_warped_into(field, &lattice, sink)
}

/// [`polygonize_terrain_into`] gathered in memory.
pub fn polygonize_terrain(field: &karst_sdf::CarvedTerrain, cell: f64) -> crate::payload::TriMesh {
    let mut mesh = crate::payload::TriMesh::default();
    let Ok(evaluations) = polygonize_terrain_into(field, cell, &mut mesh);
    mesh.field_evaluations = evaluations;
    mesh
}
