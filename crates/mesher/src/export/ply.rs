//! Binary little-endian PLY: vertices with normals, faces as uchar-counted uint lists.

use std::path::Path;

use karst_artifact::atomic;

use crate::payload::TriMesh;

/// Writes the surface as binary PLY, atomically.
pub fn write(path: &Path, surface: &TriMesh, normals: &[[f32; 3]]) -> std::io::Result<()> {
    atomic::write_with(path, |w| {
        write!(
            w,
            "ply\nformat binary_little_endian 1.0\ncomment karstgen mesh\n\
             element vertex {}\nproperty float x\nproperty float y\nproperty float z\n\
             property float nx\nproperty float ny\nproperty float nz\n\
             element face {}\nproperty list uchar uint vertex_indices\nend_header\n",
            surface.vertices.len(),
            surface.triangles.len()
        )?;
        for (p, n) in surface.vertices.iter().zip(normals) {
            for x in p.iter().chain(n) {
                w.write_all(&x.to_le_bytes())?;
            }
        }
        for t in &surface.triangles {
            w.write_all(&[3])?;
            for i in t {
                w.write_all(&i.to_le_bytes())?;
            }
        }
        Ok(())
    })
}
