//! Binary little-endian PLY (`terrain.ply`, `cave.ply`, `water.ply`; MeshLab, CloudCompare,
//! Blender): double-precision world coordinates (local f32 vertex + f64 origin, exact to the
//! micrometre at any projected coordinate) with float unit normals, the origin also in a
//! `comment origin X Y Z` header line, faces as uchar-counted uint lists; streamed.

use karst_scene::params::ExportFormat;

use crate::ExportError;
use crate::folder::{Folder, Surfaces};
use crate::frame::Frame;

/// One PLY per chosen surface.
pub fn write(folder: &mut Folder, frame: &Frame, surfaces: &Surfaces) -> Result<(), ExportError> {
    for s in &surfaces.list {
        folder.write(&format!("{}.ply", s.name), ExportFormat::Ply, |w| {
            let [x, y, z] = frame.origin();
            write!(
                w,
                "ply\nformat binary_little_endian 1.0\ncomment karstgen {}, metres, z up\ncomment origin {x:?} {y:?} {z:?}\n\
                 element vertex {}\nproperty double x\nproperty double y\nproperty double z\n\
                 property float nx\nproperty float ny\nproperty float nz\n\
                 element face {}\nproperty list uchar uint vertex_indices\nend_header\n",
                s.name,
                s.surface.vertices.len(),
                s.surface.triangles.len()
            )?;
            for (p, n) in s.surface.vertices.iter().zip(&s.normals) {
                for c in frame.world_f32(*p) {
                    w.write_all(&c.to_le_bytes())?;
                }
                for c in n {
                    w.write_all(&c.to_le_bytes())?;
                }
            }
            for t in &s.surface.triangles {
                w.write_all(&[3])?;
                for i in t {
                    w.write_all(&i.to_le_bytes())?;
                }
            }
            Ok(())
        })?;
    }
    Ok(())
}
