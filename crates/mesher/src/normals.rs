//! Vertex normals: the area-weighted mean of the normals of the triangles around a vertex.
//! They come from the mesh itself, so they cost no field evaluation and agree with the
//! triangles' orientation (out of the solid).

use glam::DVec3;

use crate::payload::TriMesh;

/// One unit normal per vertex (zero for an unused vertex).
pub fn vertex_normals(surface: &TriMesh) -> Vec<[f32; 3]> {
    let mut sum = vec![DVec3::ZERO; surface.vertices.len()];
    for t in &surface.triangles {
        let n = surface.normal(t);
        for &v in t {
            sum[v as usize] += n;
        }
    }
    sum.into_iter().map(|n| n.normalize_or_zero().as_vec3().to_array()).collect()
}
