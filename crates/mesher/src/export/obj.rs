//! Wavefront OBJ: `v`, `vn` and `f v//vn` lines, 1-based.

use std::path::Path;

use karst_artifact::atomic;

use crate::payload::TriMesh;

/// Writes the surface (with `normals` when given) as OBJ, atomically.
pub fn write(path: &Path, surface: &TriMesh, normals: &[[f32; 3]]) -> std::io::Result<()> {
    atomic::write_with(path, |w| {
        writeln!(
            w,
            "# karstgen mesh: {} vertices, {} triangles",
            surface.vertices.len(),
            surface.triangles.len()
        )?;
        for [x, y, z] in &surface.vertices {
            writeln!(w, "v {x} {y} {z}")?;
        }
        for [x, y, z] in normals {
            writeln!(w, "vn {x} {y} {z}")?;
        }
        for t in &surface.triangles {
            let [a, b, c] = t.map(|i| i + 1);
            if normals.is_empty() {
                writeln!(w, "f {a} {b} {c}")?;
            } else {
                writeln!(w, "f {a}//{a} {b}//{b} {c}//{c}")?;
            }
        }
        Ok(())
    })
}
