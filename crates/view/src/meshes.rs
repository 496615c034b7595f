//! The meshes of the view: each surface of `mesh.bin` (carved terrain, cave, water) split into
//! chunks ([`crate::chunks`]), each chunk at several levels of detail ([`crate::lod`]), each
//! level one compressed .glb ([`crate::glb`]) under `view/data/<surface>/`; and the manifest
//! the page reads to decide what to load ([`MeshView`], in run.json).
//!
//! Chunks are processed in parallel and gathered in order, so the files do not depend on the
//! number of threads.

use std::path::Path;

use rayon::prelude::*;
use serde::Serialize;

use karst_mesher::vertex_normals;
use karst_mesher::{Mesh, TriMesh};

use crate::ViewError;
use crate::chunks::{self, Chunk};
use crate::glb::{self, Quantization};
use crate::lod;

/// One surface in the manifest.
#[derive(Debug, Clone, Serialize)]
pub struct MeshView {
    /// terrain, cave or water.
    pub name: String,
    /// The lattice cell the surface was meshed at, metres.
    pub cell_size: f64,
    /// Triangles of the full surface.
    pub triangles: usize,
    pub chunks: Vec<ChunkView>,
}

/// One chunk: its box and its levels, finest first.
#[derive(Debug, Clone, Serialize)]
pub struct ChunkView {
    pub min: [f32; 3],
    pub max: [f32; 3],
    pub levels: Vec<LevelView>,
}

/// One level of a chunk.
#[derive(Debug, Clone, Serialize)]
pub struct LevelView {
    /// Path relative to view/.
    pub file: String,
    pub triangles: usize,
    /// Geometric error, metres (0 for the full chunk).
    pub error: f32,
    /// Size of the file.
    pub bytes: usize,
}

/// Writes every level of every chunk of the three surfaces under `view_dir/data/` and returns
/// the manifest.
pub fn write(view_dir: &Path, mesh: &Mesh) -> Result<Vec<MeshView>, ViewError> {
    let cells = [mesh.cell_size, mesh.cave_cell_size, mesh.cave_cell_size];
    mesh.surfaces()
        .into_iter()
        .zip(cells)
        .filter(|((_, surface), _)| !surface.triangles.is_empty())
        .map(|((name, surface), cell)| write_surface(view_dir, name, surface, cell))
        .collect()
}

fn write_surface(
    view_dir: &Path,
    name: &str,
    surface: &TriMesh,
    cell_size: f64,
) -> Result<MeshView, ViewError> {
    let normals = vertex_normals(surface);
    let chunks = chunks::split(surface, &normals, chunks::TARGET_TRIANGLES);
    let (min, max) = bounds(&chunks);
    let q = Quantization::over(min, max);
    let folder = view_dir.join("data").join(name);
    std::fs::create_dir_all(&folder).map_err(|source| ViewError::Write { path: folder.clone(), source })?;
    let chunks = chunks
        .par_iter()
        .enumerate()
        .map(|(i, chunk)| write_chunk(view_dir, &format!("data/{name}/c{i:03}"), chunk, &q, cell_size as f32))
        .collect::<Result<Vec<_>, _>>()?;
    Ok(MeshView { name: name.into(), cell_size, triangles: surface.triangles.len(), chunks })
}

fn write_chunk(
    view_dir: &Path,
    stem: &str,
    chunk: &Chunk,
    q: &Quantization,
    cell_size: f32,
) -> Result<ChunkView, ViewError> {
    let (min, max) = chunk.bounds();
    let levels = lod::levels(chunk, cell_size)
        .iter()
        .enumerate()
        .map(|(k, level)| {
            let file = format!("{stem}-l{k}.glb");
            let path = view_dir.join(&file);
            let bytes = glb::encode(&level.chunk, q).map_err(|e| ViewError::Encode {
                path: path.clone(),
                what: "chunk".into(),
                detail: e.to_string(),
            })?;
            std::fs::write(&path, &bytes).map_err(|source| ViewError::Write { path, source })?;
            Ok(LevelView {
                file,
                triangles: level.chunk.indices.len() / 3,
                error: level.error,
                bytes: bytes.len(),
            })
        })
        .collect::<Result<Vec<_>, ViewError>>()?;
    Ok(ChunkView { min, max, levels })
}

fn bounds(chunks: &[Chunk]) -> ([f32; 3], [f32; 3]) {
    chunks.iter().map(Chunk::bounds).fold(([f32::INFINITY; 3], [f32::NEG_INFINITY; 3]), |(lo, hi), (a, b)| {
        ([0, 1, 2].map(|i| lo[i].min(a[i])), [0, 1, 2].map(|i| hi[i].max(b[i])))
    })
}
