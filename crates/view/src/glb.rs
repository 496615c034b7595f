//! One level of one chunk as binary glTF 2.0, compressed the way three.js's GLTFLoader decodes
//! natively: KHR_mesh_quantization (positions as 16-bit integers, normals as 8-bit normalized
//! integers) and EXT_meshopt_compression (meshoptimizer's vertex and index codecs on the
//! buffer views; the loader decodes them with `MeshoptDecoder`). The file is laid out by the
//! shared writer (`karst-gltf`), which also holds the quantization grid.
//!
//! Quantization: every chunk of a surface shares one [`Quantization`], so that the chunks meet
//! exactly; a chunk stores its integers relative to its own lowest grid point, and the glTF
//! node's scale (the step) and translation (that grid point) turn them back into metres.
//!
//! Axes: glTF is Y-up, the scene Z-up. The node also carries the −90° rotation about x that
//! turns (x, y, z) into (x, z, −y) (as the export's karst.glb does), so the files open upright
//! in any glTF viewer; the page turns them back.
//!
//! The EXT_meshopt_compression buffer views use meshoptimizer's vertex codec version 0 (the
//! extension's), index codec version 1 (TRIANGLES mode). The uncompressed fallback buffer has
//! no data (the extension is required).

use serde_json::json;

pub use karst_gltf::quantize::Quantization;
use karst_gltf::quantize::snorm;
use karst_gltf::{BYTE, Gltf, MESHOPT, QUANTIZATION, UNSIGNED_INT, UNSIGNED_SHORT, Z_UP_TO_Y_UP};

use crate::chunks::Chunk;

/// Why a chunk cannot be encoded: meshoptimizer's codecs or the glTF document refused it.
#[derive(Debug, thiserror::Error)]
pub enum GlbError {
    /// A vertex or index stream meshoptimizer cannot encode.
    #[error("meshoptimizer: {0}")]
    Codec(#[from] meshopt::Error),
    /// The glTF document or its binary container.
    #[error(transparent)]
    Gltf(#[from] karst_gltf::GltfError),
}

/// The .glb of one chunk level.
pub fn encode(chunk: &Chunk, q: &Quantization) -> Result<Vec<u8>, GlbError> {
    let grid: Vec<[u32; 3]> = chunk.vertices.iter().map(|v| q.grid(v.position)).collect();
    let low = grid.iter().fold([u32::MAX; 3], |m, g| [0, 1, 2].map(|a| m[a].min(g[a])));
    let positions: Vec<[u16; 4]> =
        grid.iter().map(|g| [g[0] - low[0], g[1] - low[1], g[2] - low[2], 0].map(|c| c as u16)).collect();
    let normals: Vec<[i8; 4]> = chunk.vertices.iter().map(|v| snorm(v.normal)).collect();
    let n = positions.len();
    let wide = n > usize::from(u16::MAX);
    let index_size = if wide { 4 } else { 2 };
    let (qmin, qmax) = positions.iter().fold(([u16::MAX; 3], [0u16; 3]), |(lo, hi), p| {
        ([0, 1, 2].map(|a| lo[a].min(p[a])), [0, 1, 2].map(|a| hi[a].max(p[a])))
    });
    let mut b = Gltf::new();
    b.require(&[MESHOPT, QUANTIZATION]);
    let stream = meshopt::encode_vertex_buffer_level(&positions, 2, Some(0))?;
    let view = b.compressed_view(stream, 8, n, "ATTRIBUTES");
    b.accessor(json!({ "bufferView": view, "componentType": UNSIGNED_SHORT, "count": n, "type": "VEC3", "min": qmin, "max": qmax }));
    let stream = meshopt::encode_vertex_buffer_level(&normals, 2, Some(0))?;
    let view = b.compressed_view(stream, 4, n, "ATTRIBUTES");
    b.accessor(
        json!({ "bufferView": view, "componentType": BYTE, "normalized": true, "count": n, "type": "VEC3" }),
    );
    let stream = meshopt::encode_index_buffer(&chunk.indices, n)?;
    let view = b.compressed_view(stream, index_size, chunk.indices.len(), "TRIANGLES");
    b.accessor(
        json!({ "bufferView": view, "componentType": if wide { UNSIGNED_INT } else { UNSIGNED_SHORT },
        "count": chunk.indices.len(), "type": "SCALAR" }),
    );
    b.mesh(
        json!({ "primitives": [{ "attributes": { "POSITION": 0, "NORMAL": 1 }, "indices": 2, "mode": 4 }] }),
    );
    let corner = q.point(low);
    let translation = [corner[0], corner[2], -corner[1]];
    let scale = [q.step; 3];
    b.node(json!({ "mesh": 0, "translation": translation, "rotation": Z_UP_TO_Y_UP, "scale": scale }));
    let glb = b.finish("karstgen karst-view", json!([{ "nodes": [0] }]))?;
    Ok(glb.to_vec())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::chunks::{split, tests::grid};

    /// The JSON chunk and the BIN chunk of a .glb.
    fn parts(glb: &[u8]) -> (serde_json::Value, &[u8]) {
        assert_eq!(&glb[..4], b"glTF");
        assert_eq!(u32::from_le_bytes(glb[8..12].try_into().unwrap()) as usize, glb.len());
        let json_len = u32::from_le_bytes(glb[12..16].try_into().unwrap()) as usize;
        let json = serde_json::from_slice(&glb[20..20 + json_len]).unwrap();
        (json, &glb[20 + json_len + 8..])
    }

    #[test]
    fn decoding_the_streams_gives_back_the_chunk() {
        let mut surface = grid(30);
        for v in &mut surface.vertices {
            v[2] = 0.25 * v[0] - 3.0;
        }
        let normals = vec![[0.0, 0.6, 0.8]; surface.vertices.len()];
        let chunk = split(&surface, &normals, usize::MAX).remove(0);
        let (min, max) = chunk.bounds();
        let q = Quantization::over(min, max);
        let glb = encode(&chunk, &q).unwrap();
        let (doc, bin) = parts(&glb);
        assert_eq!(doc["extensionsRequired"], json!([MESHOPT, QUANTIZATION]));
        let ext = |i: usize| &doc["bufferViews"][i]["extensions"]["EXT_meshopt_compression"];
        let stream = |i: usize| {
            let (o, l) = (
                ext(i)["byteOffset"].as_u64().unwrap() as usize,
                ext(i)["byteLength"].as_u64().unwrap() as usize,
            );
            &bin[o..o + l]
        };
        let n = chunk.vertices.len();
        let positions: Vec<[u16; 4]> = meshopt::decode_vertex_buffer(stream(0), n).unwrap();
        let normals: Vec<[i8; 4]> = meshopt::decode_vertex_buffer(stream(1), n).unwrap();
        let indices: Vec<u16> = meshopt::decode_index_buffer(stream(2), chunk.indices.len()).unwrap();
        let node = &doc["nodes"][0];
        let (t, s) = (&node["translation"], node["scale"][0].as_f64().unwrap());
        for (i, v) in chunk.vertices.iter().enumerate() {
            // Undo the node: scale, then the rotation (x, y, z) → (x, z, −y), then translate.
            let p = positions[i].map(f64::from);
            let t = [0, 1, 2].map(|a| t[a].as_f64().unwrap());
            let world = [p[0] * s + t[0], p[1] * s - t[2], p[2] * s + t[1]];
            for (w, x) in world.iter().zip(v.position) {
                assert!((w - f64::from(x)).abs() <= q.step, "vertex {i}: {world:?} vs {:?}", v.position);
            }
            assert_eq!(normals[i], [0, 76, 102, 0]);
        }
        // The index codec may rotate a triangle's corners (keeping its winding).
        let canonical = |t: &[u32]| (0..3).map(|r| [t[r], t[(r + 1) % 3], t[(r + 2) % 3]]).min().unwrap();
        let decoded: Vec<u32> = indices.iter().map(|&i| u32::from(i)).collect();
        let same = decoded.chunks(3).zip(chunk.indices.chunks(3)).all(|(a, b)| canonical(a) == canonical(b));
        assert!(same && decoded.len() == chunk.indices.len(), "the triangles come back, in order");
    }
}
