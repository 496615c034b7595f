//! Exports of the meshes for other tools: Wavefront OBJ, binary PLY and binary glTF (.glb),
//! each with vertex normals. The carved terrain's OBJ is `mesh.obj` in the output folder; the
//! rest go under `export/`: `terrain.{ply,glb}`, `cave.{obj,ply,glb}` and `water.{obj,ply,glb}`.

pub mod glb;
pub mod obj;
pub mod ply;

use std::path::{Path, PathBuf};

use crate::Mesh;
use crate::normals::vertex_normals;
use crate::payload::TriMesh;

/// Name of the export folder inside the output folder.
pub const FOLDER: &str = "export";

/// Name of the carved terrain's OBJ in the output folder.
pub const OBJ_NAME: &str = "mesh.obj";

/// Writes `dir/mesh.obj` and the files under `dir/export/`, and returns their paths.
pub fn write_all(dir: &Path, mesh: &Mesh) -> std::io::Result<Vec<PathBuf>> {
    let folder = dir.join(FOLDER);
    std::fs::create_dir_all(&folder)?;
    let mut written = write_surface(&mesh.terrain, Some(dir.join(OBJ_NAME)), &folder, "terrain")?;
    written.extend(write_surface(&mesh.cave, Some(folder.join("cave.obj")), &folder, "cave")?);
    written.extend(write_surface(&mesh.water, Some(folder.join("water.obj")), &folder, "water")?);
    Ok(written)
}

fn write_surface(
    surface: &TriMesh,
    obj: Option<PathBuf>,
    folder: &Path,
    name: &str,
) -> std::io::Result<Vec<PathBuf>> {
    let normals = vertex_normals(surface);
    let [ply, glb] = ["ply", "glb"].map(|ext| folder.join(format!("{name}.{ext}")));
    ply::write(&ply, surface, &normals)?;
    glb::write(&glb, surface, &normals)?;
    let mut written = vec![ply, glb];
    if let Some(path) = obj {
        obj::write(&path, surface, &normals)?;
        written.push(path);
    }
    Ok(written)
}
