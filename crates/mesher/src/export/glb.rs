//! Binary glTF 2.0 (.glb): a 12-byte header, a JSON chunk and a BIN chunk holding positions,
//! normals and 32-bit indices, one mesh with one triangle primitive.
//!
//! glTF is Y-up and right-handed while the scene is Z-up: positions and normals are turned by
//! −90° about x, (x, y, z) → (x, z, −y), a rotation, so winding and orientation are kept
//! (glTF's front faces are counter-clockwise, as ours seen from outside the solid).

use std::path::Path;

use serde_json::{Value, json};

use karst_artifact::atomic;

use crate::payload::TriMesh;

const MAGIC: &[u8; 4] = b"glTF";
const JSON_CHUNK: u32 = 0x4E4F_534A;
const BIN_CHUNK: u32 = 0x004E_4942;
const FLOAT: u32 = 5126;
const UNSIGNED_INT: u32 = 5125;
const ARRAY_BUFFER: u32 = 34962;
const ELEMENT_ARRAY_BUFFER: u32 = 34963;

/// Writes the surface as .glb, atomically.
pub fn write(path: &Path, surface: &TriMesh, normals: &[[f32; 3]]) -> std::io::Result<()> {
    let bytes = encode(surface, normals);
    atomic::write_with(path, |w| w.write_all(&bytes))
}

/// The .glb file of a surface.
pub fn encode(surface: &TriMesh, normals: &[[f32; 3]]) -> Vec<u8> {
    let y_up = |[x, y, z]: [f32; 3]| [x, z, -y];
    let positions: Vec<[f32; 3]> = surface.vertices.iter().copied().map(y_up).collect();
    let normals: Vec<[f32; 3]> = normals.iter().copied().map(y_up).collect();
    let mut bin = Vec::with_capacity((positions.len() * 24) + surface.triangles.len() * 12);
    for v in positions.iter().chain(&normals).flatten() {
        bin.extend_from_slice(&v.to_le_bytes());
    }
    for i in surface.triangles.iter().flatten() {
        bin.extend_from_slice(&i.to_le_bytes());
    }
    let document = if surface.triangles.is_empty() {
        empty_document()
    } else {
        document(surface, &positions, bin.len())
    };
    let mut json = serde_json::to_vec(&document).expect("a JSON value serializes");
    pad(&mut json, b' ');
    pad(&mut bin, 0);
    let chunks = [(JSON_CHUNK, json), (BIN_CHUNK, bin)];
    let chunks = chunks.iter().filter(|(_, data)| !data.is_empty());
    let total = 12 + chunks.clone().map(|(_, data)| 8 + data.len()).sum::<usize>();
    let mut out = Vec::with_capacity(total);
    out.extend_from_slice(MAGIC);
    out.extend_from_slice(&2u32.to_le_bytes());
    out.extend_from_slice(&(total as u32).to_le_bytes());
    for (kind, data) in chunks {
        out.extend_from_slice(&(data.len() as u32).to_le_bytes());
        out.extend_from_slice(&kind.to_le_bytes());
        out.extend_from_slice(data);
    }
    out
}

fn document(surface: &TriMesh, positions: &[[f32; 3]], bin_len: usize) -> Value {
    let n = positions.len();
    let vec3_bytes = n * 12;
    let (mut min, mut max) = ([f32::INFINITY; 3], [f32::NEG_INFINITY; 3]);
    for p in positions {
        for a in 0..3 {
            min[a] = min[a].min(p[a]);
            max[a] = max[a].max(p[a]);
        }
    }
    json!({
        "asset": { "version": "2.0", "generator": "karstgen" },
        "scene": 0,
        "scenes": [{ "nodes": [0] }],
        "nodes": [{ "mesh": 0 }],
        "meshes": [{ "primitives": [{ "attributes": { "POSITION": 0, "NORMAL": 1 }, "indices": 2, "mode": 4 }] }],
        "buffers": [{ "byteLength": bin_len }],
        "bufferViews": [
            { "buffer": 0, "byteOffset": 0, "byteLength": vec3_bytes, "target": ARRAY_BUFFER },
            { "buffer": 0, "byteOffset": vec3_bytes, "byteLength": vec3_bytes, "target": ARRAY_BUFFER },
            { "buffer": 0, "byteOffset": 2 * vec3_bytes, "byteLength": surface.triangles.len() * 12,
              "target": ELEMENT_ARRAY_BUFFER },
        ],
        "accessors": [
            { "bufferView": 0, "componentType": FLOAT, "count": n, "type": "VEC3", "min": min, "max": max },
            { "bufferView": 1, "componentType": FLOAT, "count": n, "type": "VEC3" },
            { "bufferView": 2, "componentType": UNSIGNED_INT, "count": surface.triangles.len() * 3,
              "type": "SCALAR" },
        ],
    })
}

/// A valid scene with nothing in it (glTF forbids empty buffers and accessors).
fn empty_document() -> Value {
    json!({ "asset": { "version": "2.0", "generator": "karstgen" }, "scene": 0, "scenes": [{ "nodes": [] }] })
}

fn pad(data: &mut Vec<u8>, with: u8) {
    while !data.len().is_multiple_of(4) {
        data.push(with);
    }
}
