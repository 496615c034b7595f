//! One level of one chunk as binary glTF 2.0, compressed the way three.js's GLTFLoader decodes
//! natively: KHR_mesh_quantization (positions as 16-bit integers, normals as 8-bit normalized
//! integers) and EXT_meshopt_compression (meshoptimizer's vertex and index codecs on the
//! buffer views; the loader decodes them with `MeshoptDecoder`).
//!
//! Quantization: every chunk of a surface shares one [`Quantization`], a grid of step `step`
//! from the surface's lowest corner, so that a vertex on the seam of two chunks gets the same
//! integer position in both and the chunks meet exactly. A chunk stores its integers relative
//! to its own lowest grid point; the glTF node's scale (the step) and translation (that grid
//! point) turn them back into metres.
//!
//! Axes: glTF is Y-up, the scene Z-up. The node also carries the −90° rotation about x that
//! turns (x, y, z) into (x, z, −y) (as `karst-mesher`'s exports do), so the files open upright
//! in any glTF viewer; the page turns them back.
//!
//! The EXT_meshopt_compression buffer views use meshoptimizer's vertex codec version 0 (the
//! extension's), index codec version 1 (TRIANGLES mode). The uncompressed fallback buffer has
//! no data (the extension is required).

use serde_json::{Value, json};

use crate::chunks::Chunk;

const MAGIC: &[u8; 4] = b"glTF";
const JSON_CHUNK: u32 = 0x4E4F_534A;
const BIN_CHUNK: u32 = 0x004E_4942;
const BYTE: u32 = 5120;
const UNSIGNED_SHORT: u32 = 5123;
const UNSIGNED_INT: u32 = 5125;
const ARRAY_BUFFER: u32 = 34962;
const ELEMENT_ARRAY_BUFFER: u32 = 34963;
const EXTENSIONS: [&str; 2] = ["EXT_meshopt_compression", "KHR_mesh_quantization"];
/// Largest quantized coordinate.
const Q_MAX: f64 = 65535.0;
/// The unit quaternion of −90° about x: Z-up to glTF's Y-up.
const Z_UP_TO_Y_UP: [f64; 4] = [-std::f64::consts::FRAC_1_SQRT_2, 0.0, 0.0, std::f64::consts::FRAC_1_SQRT_2];

/// The integer grid positions of one surface are quantized on.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Quantization {
    pub origin: [f64; 3],
    /// Grid step, metres.
    pub step: f64,
}

impl Quantization {
    /// The grid over the box `min`..`max` with 2¹⁶ steps along its longest side.
    pub fn over(min: [f32; 3], max: [f32; 3]) -> Quantization {
        let extent = (0..3).map(|a| f64::from(max[a]) - f64::from(min[a])).fold(0.0, f64::max);
        let step = if extent > 0.0 { extent / Q_MAX } else { 1.0 };
        Quantization { origin: min.map(f64::from), step }
    }

    /// The grid coordinates of `p`.
    fn grid(&self, p: [f32; 3]) -> [u32; 3] {
        [0, 1, 2].map(|a| ((f64::from(p[a]) - self.origin[a]) / self.step).round().clamp(0.0, Q_MAX) as u32)
    }
}

/// The .glb of one chunk level.
pub fn encode(chunk: &Chunk, q: &Quantization) -> Result<Vec<u8>, String> {
    let grid: Vec<[u32; 3]> = chunk.vertices.iter().map(|v| q.grid(v.position)).collect();
    let low = grid.iter().fold([u32::MAX; 3], |m, g| [0, 1, 2].map(|a| m[a].min(g[a])));
    let positions: Vec<[u16; 4]> =
        grid.iter().map(|g| [g[0] - low[0], g[1] - low[1], g[2] - low[2], 0].map(|c| c as u16)).collect();
    let normals: Vec<[i8; 4]> = chunk.vertices.iter().map(|v| snorm(v.normal)).collect();
    let n = positions.len();
    let wide = n > usize::from(u16::MAX);
    let index_size = if wide { 4 } else { 2 };
    let codec = |e: meshopt::Error| e.to_string();
    let streams = [
        meshopt::encode_vertex_buffer_level(&positions, 2, Some(0)).map_err(codec)?,
        meshopt::encode_vertex_buffer_level(&normals, 2, Some(0)).map_err(codec)?,
        meshopt::encode_index_buffer(&chunk.indices, n).map_err(codec)?,
    ];
    let mut bin = Vec::new();
    let mut offsets = [0usize; 3];
    for (offset, stream) in offsets.iter_mut().zip(&streams) {
        *offset = bin.len();
        bin.extend_from_slice(stream);
        pad(&mut bin, 0);
    }
    let translation = {
        let corner = [0, 1, 2].map(|a| q.origin[a] + f64::from(low[a]) * q.step);
        [corner[0], corner[2], -corner[1]]
    };
    let (qmin, qmax) = positions.iter().fold(([u16::MAX; 3], [0u16; 3]), |(lo, hi), p| {
        ([0, 1, 2].map(|a| lo[a].min(p[a])), [0, 1, 2].map(|a| hi[a].max(p[a])))
    });
    let raw = [n * 8, n * 4, chunk.indices.len() * index_size];
    let view = |i: usize, stride: usize, count: usize, mode: &str, target: u32| {
        json!({
            "buffer": 1, "byteOffset": raw[..i].iter().sum::<usize>(), "byteLength": raw[i],
            "byteStride": if target == ARRAY_BUFFER { Some(stride) } else { None }, "target": target,
            "extensions": { "EXT_meshopt_compression": {
                "buffer": 0, "byteOffset": offsets[i], "byteLength": streams[i].len(),
                "byteStride": stride, "count": count, "mode": mode,
            }},
        })
    };
    let mut views = vec![
        view(0, 8, n, "ATTRIBUTES", ARRAY_BUFFER),
        view(1, 4, n, "ATTRIBUTES", ARRAY_BUFFER),
        view(2, index_size, chunk.indices.len(), "TRIANGLES", ELEMENT_ARRAY_BUFFER),
    ];
    for v in &mut views {
        if v["byteStride"].is_null() {
            v.as_object_mut().expect("a view is an object").remove("byteStride");
        }
    }
    let scale = [q.step; 3];
    let document = json!({
        "asset": { "version": "2.0", "generator": "karstgen karst-view" },
        "extensionsUsed": EXTENSIONS,
        "extensionsRequired": EXTENSIONS,
        "scene": 0,
        "scenes": [{ "nodes": [0] }],
        "nodes": [{ "mesh": 0, "translation": translation, "rotation": Z_UP_TO_Y_UP, "scale": scale }],
        "meshes": [{ "primitives": [{ "attributes": { "POSITION": 0, "NORMAL": 1 }, "indices": 2, "mode": 4 }] }],
        "buffers": [
            { "byteLength": bin.len() },
            { "byteLength": raw.iter().sum::<usize>(), "extensions": { "EXT_meshopt_compression": { "fallback": true } } },
        ],
        "bufferViews": views,
        "accessors": [
            { "bufferView": 0, "componentType": UNSIGNED_SHORT, "count": n, "type": "VEC3", "min": qmin, "max": qmax },
            { "bufferView": 1, "componentType": BYTE, "normalized": true, "count": n, "type": "VEC3" },
            { "bufferView": 2, "componentType": if wide { UNSIGNED_INT } else { UNSIGNED_SHORT },
              "count": chunk.indices.len(), "type": "SCALAR" },
        ],
    });
    Ok(container(&document, bin))
}

/// A unit vector as three signed bytes (and a padding byte).
fn snorm(v: [f32; 3]) -> [i8; 4] {
    let c = |x: f32| (x.clamp(-1.0, 1.0) * 127.0).round() as i8;
    [c(v[0]), c(v[1]), c(v[2]), 0]
}

/// The GLB container: header, JSON chunk, BIN chunk.
fn container(document: &Value, mut bin: Vec<u8>) -> Vec<u8> {
    let mut json = serde_json::to_vec(document).expect("a JSON value serializes");
    pad(&mut json, b' ');
    pad(&mut bin, 0);
    let total = 12 + 8 + json.len() + 8 + bin.len();
    let mut out = Vec::with_capacity(total);
    out.extend_from_slice(MAGIC);
    out.extend_from_slice(&2u32.to_le_bytes());
    out.extend_from_slice(&(total as u32).to_le_bytes());
    for (kind, data) in [(JSON_CHUNK, &json), (BIN_CHUNK, &bin)] {
        out.extend_from_slice(&(data.len() as u32).to_le_bytes());
        out.extend_from_slice(&kind.to_le_bytes());
        out.extend_from_slice(data);
    }
    out
}

fn pad(data: &mut Vec<u8>, with: u8) {
    while !data.len().is_multiple_of(4) {
        data.push(with);
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::chunks::{split, tests::grid};

    /// The JSON chunk and the BIN chunk of a .glb.
    fn parts(glb: &[u8]) -> (Value, &[u8]) {
        assert_eq!(&glb[..4], MAGIC);
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
        assert_eq!(doc["extensionsRequired"], json!(EXTENSIONS));
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
