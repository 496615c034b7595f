//! Assembling a glTF document: its arrays (buffer views, accessors, materials, meshes, nodes)
//! and the blocks of its binary buffer, each block a deferred writer of known length.
//!
//! Buffer 0 is the GLB's binary chunk. Every block ends on a 4-byte boundary (zero padding
//! after it), as glTF requires of accessor data. A meshopt-compressed view stores its stream in
//! buffer 0 and points, as EXT_meshopt_compression asks, into buffer 1: a fallback buffer that
//! only declares its length (the extension is then required).

use std::io::{self, Write};

use serde_json::{Value, json};

use crate::container::{Fill, Glb};
use crate::{ARRAY_BUFFER, ELEMENT_ARRAY_BUFFER, FLOAT, GltfError, MESHOPT, UNSIGNED_INT};

/// A glTF document being assembled; [`Gltf::finish`] lays out the file.
#[derive(Default)]
pub struct Gltf<'a> {
    views: Vec<Value>,
    accessors: Vec<Value>,
    materials: Vec<Value>,
    meshes: Vec<Value>,
    nodes: Vec<Value>,
    extensions: Vec<&'static str>,
    blocks: Vec<Fill<'a>>,
    /// Bytes of buffer 0 so far (padded).
    length: usize,
    /// Bytes of the meshopt fallback buffer (buffer 1) so far.
    fallback: usize,
}

impl<'a> Gltf<'a> {
    pub fn new() -> Gltf<'a> {
        Gltf::default()
    }

    /// Declares extensions the file uses and requires, in this order.
    pub fn require(&mut self, extensions: &[&'static str]) {
        self.extensions.extend(extensions);
    }

    /// Appends `bytes` bytes written by `write` to buffer 0, padded to 4.
    fn block(&mut self, bytes: usize, write: impl Fn(&mut dyn Write) -> io::Result<()> + 'a) -> usize {
        let offset = self.length;
        self.blocks.push(Box::new(write));
        self.length += bytes;
        let pad = self.length.next_multiple_of(4) - self.length;
        if pad > 0 {
            self.blocks.push(Box::new(move |w| w.write_all(&[0u8; 3][..pad])));
            self.length += pad;
        }
        offset
    }

    /// A plain buffer view of `bytes` bytes that `write` streams; returns the view's index.
    pub fn view(
        &mut self,
        bytes: usize,
        target: u32,
        write: impl Fn(&mut dyn Write) -> io::Result<()> + 'a,
    ) -> usize {
        let offset = self.block(bytes, write);
        self.views.push(json!({ "buffer": 0, "byteOffset": offset, "byteLength": bytes, "target": target }));
        self.views.len() - 1
    }

    /// A view compressed by meshoptimizer: `stream` (the codec's output) decodes to `count`
    /// elements of `stride` bytes in `mode` (`ATTRIBUTES`, `TRIANGLES`); vertex data carries its
    /// stride, indices do not. Returns the view's index.
    pub fn compressed_view(&mut self, stream: Vec<u8>, stride: usize, count: usize, mode: &str) -> usize {
        let (raw, compressed) = (stride * count, stream.len());
        let offset = self.block(compressed, move |w| w.write_all(&stream));
        let target = if mode == "ATTRIBUTES" { ARRAY_BUFFER } else { ELEMENT_ARRAY_BUFFER };
        let mut view = json!({
            "buffer": 1, "byteOffset": self.fallback, "byteLength": raw, "target": target,
            "extensions": { MESHOPT: {
                "buffer": 0, "byteOffset": offset, "byteLength": compressed,
                "byteStride": stride, "count": count, "mode": mode,
            }},
        });
        if target == ARRAY_BUFFER {
            view["byteStride"] = json!(stride);
        }
        self.fallback += raw;
        self.views.push(view);
        self.views.len() - 1
    }

    pub fn accessor(&mut self, accessor: Value) -> usize {
        self.accessors.push(accessor);
        self.accessors.len() - 1
    }

    /// A matte material of RGBA `colour`, blended when not opaque.
    pub fn material(&mut self, name: &str, colour: [f32; 4]) -> usize {
        let mut m = json!({ "name": name, "pbrMetallicRoughness": { "baseColorFactor": colour, "metallicFactor": 0.0, "roughnessFactor": 0.9 } });
        if colour[3] < 1.0 {
            m["alphaMode"] = json!("BLEND");
        }
        self.materials.push(m);
        self.materials.len() - 1
    }

    pub fn mesh(&mut self, mesh: Value) -> usize {
        self.meshes.push(mesh);
        self.meshes.len() - 1
    }

    pub fn node(&mut self, node: Value) -> usize {
        self.nodes.push(node);
        self.nodes.len() - 1
    }

    /// A float VEC3 accessor over `count` points (already Y-up), with the bounds glTF requires.
    pub fn positions(&mut self, points: impl Fn(usize) -> [f32; 3] + 'a, count: usize) -> usize {
        let (mut min, mut max) = ([f32::INFINITY; 3], [f32::NEG_INFINITY; 3]);
        for p in (0..count).map(&points) {
            for a in 0..3 {
                min[a] = min[a].min(p[a]);
                max[a] = max[a].max(p[a]);
            }
        }
        let view = self.view(count * 12, ARRAY_BUFFER, move |w| {
            (0..count).try_for_each(|i| points(i).iter().try_for_each(|c| w.write_all(&c.to_le_bytes())))
        });
        self.accessor(json!({ "bufferView": view, "componentType": FLOAT, "count": count, "type": "VEC3", "min": min, "max": max }))
    }

    /// A float VEC3 accessor over `count` directions (already Y-up), without bounds.
    pub fn directions(&mut self, vectors: impl Fn(usize) -> [f32; 3] + 'a, count: usize) -> usize {
        let view = self.view(count * 12, ARRAY_BUFFER, move |w| {
            (0..count).try_for_each(|i| vectors(i).iter().try_for_each(|c| w.write_all(&c.to_le_bytes())))
        });
        self.accessor(json!({ "bufferView": view, "componentType": FLOAT, "count": count, "type": "VEC3" }))
    }

    /// A 32-bit index accessor of `count` indices.
    pub fn indices(&mut self, count: usize, index: impl Fn(usize) -> u32 + 'a) -> usize {
        let view = self.view(count * 4, ELEMENT_ARRAY_BUFFER, move |w| {
            (0..count).try_for_each(|i| w.write_all(&index(i).to_le_bytes()))
        });
        self.accessor(
            json!({ "bufferView": view, "componentType": UNSIGNED_INT, "count": count, "type": "SCALAR" }),
        )
    }

    /// The file: `scenes` (default scene 0) over the nodes, the asset naming `generator`; the
    /// arrays that hold something, the buffers, and the required extensions.
    pub fn finish(self, generator: &str, scenes: Value) -> Result<Glb<'a>, GltfError> {
        let mut document = json!({
            "asset": { "version": "2.0", "generator": generator },
            "scene": 0,
            "scenes": scenes,
            "nodes": self.nodes,
        });
        if !self.extensions.is_empty() {
            document["extensionsUsed"] = json!(self.extensions);
            document["extensionsRequired"] = json!(self.extensions);
        }
        if self.length > 0 {
            for (key, list) in [
                ("meshes", self.meshes),
                ("materials", self.materials),
                ("accessors", self.accessors),
                ("bufferViews", self.views),
            ] {
                if !list.is_empty() {
                    document[key] = Value::Array(list);
                }
            }
            let mut buffers = vec![json!({ "byteLength": self.length })];
            if self.fallback > 0 {
                buffers.push(
                    json!({ "byteLength": self.fallback, "extensions": { MESHOPT: { "fallback": true } } }),
                );
            }
            document["buffers"] = json!(buffers);
        }
        Glb::new(&document, self.blocks, self.length)
    }
}
