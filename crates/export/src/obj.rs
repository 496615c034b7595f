//! Wavefront OBJ (`terrain.obj`, `cave.obj`, `water.obj`): `v` lines in world coordinates,
//! `vn` unit normals and `f a//a b//b c//c` triangles, 1-based; streamed to the file.

use karst_scene::params::ExportFormat;

use crate::ExportError;
use crate::folder::{Folder, Surfaces};
use crate::frame::Frame;

/// One OBJ per chosen surface.
pub fn write(folder: &mut Folder, frame: &Frame, surfaces: &Surfaces) -> Result<(), ExportError> {
    for s in &surfaces.list {
        folder.write(&format!("{}.obj", s.name), ExportFormat::Obj, |w| {
            let (vertices, triangles) = (&s.surface.vertices, &s.surface.triangles);
            writeln!(
                w,
                "# karstgen {}: {} vertices, {} triangles, metres, z up",
                s.name,
                vertices.len(),
                triangles.len()
            )?;
            writeln!(w, "o {}", s.name)?;
            for v in vertices {
                let [x, y, z] = frame.world_f32(*v);
                writeln!(w, "v {x} {y} {z}")?;
            }
            for [x, y, z] in &s.normals {
                writeln!(w, "vn {x} {y} {z}")?;
            }
            for t in triangles {
                let [a, b, c] = t.map(|i| i + 1);
                writeln!(w, "f {a}//{a} {b}//{b} {c}//{c}")?;
            }
            Ok(())
        })?;
    }
    Ok(())
}
