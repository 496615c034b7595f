//! Binary glTF 2.0 (`karst.glb`: Blender, three.js, game engines; checked by the Khronos
//! glTF-Validator): one scene whose nodes are named `terrain`, `cave`, `water` (the chosen
//! surfaces, triangles with normals) and `network` (the conduit segments as line primitives,
//! one per conduit type, each with a material named and coloured after its type).
//!
//! glTF is Y-up, the scene Z-up: positions and normals are turned by −90° about x,
//! (x, y, z) → (x, z, −y), a rotation, so winding and orientation are kept. Positions are
//! single-precision local coordinates (sub-millimetre within a few kilometres of the origin);
//! the four nodes are the children of a root node `karst` translated by the world position of
//! the local origin (turned Y-up, written as JSON numbers, i.e. in f64), so that a viewer
//! places the model at its world coordinates; the scene's `extras.origin` holds the same origin
//! z up. The file is
//! streamed: the JSON chunk is built from the counts, then every buffer goes straight from the
//! artifacts to the file.

use std::io::{self, Write};

use serde_json::{Value, json};

use karst_scene::params::ExportFormat;
use karst_skeleton::ConduitType;

use crate::ExportError;
use crate::folder::{Fill, Folder, Surfaces};
use crate::frame::Frame;
use crate::network::NetworkView;

const MAGIC: &[u8; 4] = b"glTF";
const JSON_CHUNK: u32 = 0x4E4F_534A;
const BIN_CHUNK: u32 = 0x004E_4942;
const FLOAT: u32 = 5126;
const UNSIGNED_INT: u32 = 5125;
const ARRAY_BUFFER: u32 = 34962;
const ELEMENT_ARRAY_BUFFER: u32 = 34963;
const TRIANGLES: u32 = 4;
const LINES: u32 = 1;

/// RGBA colour of each conduit type's lines, and of each surface.
fn type_colour(kind: ConduitType) -> [f32; 4] {
    match kind {
        ConduitType::Epikarst => [0.55, 0.35, 0.15, 1.0],
        ConduitType::Tube => [0.85, 0.2, 0.2, 1.0],
        ConduitType::Canyon => [0.95, 0.65, 0.1, 1.0],
        ConduitType::Keyhole => [0.6, 0.25, 0.75, 1.0],
        ConduitType::Passage => [0.2, 0.7, 0.3, 1.0],
        ConduitType::Bed => [0.15, 0.45, 0.85, 1.0],
        ConduitType::Chamber => [0.9, 0.9, 0.9, 1.0],
    }
}

fn surface_colour(name: &str) -> [f32; 4] {
    match name {
        "terrain" => [0.62, 0.58, 0.5, 1.0],
        "cave" => [0.78, 0.72, 0.6, 1.0],
        _ => [0.2, 0.45, 0.8, 0.6],
    }
}

fn y_up([x, y, z]: [f32; 3]) -> [f32; 3] {
    [x, z, -y]
}

/// The document being assembled and the byte blocks of its buffer, in order.
struct Builder<'a> {
    views: Vec<Value>,
    accessors: Vec<Value>,
    materials: Vec<Value>,
    meshes: Vec<Value>,
    nodes: Vec<Value>,
    blocks: Vec<Block<'a>>,
    length: usize,
}

/// How to write one block of the buffer.
struct Block<'a> {
    write: Fill<'a>,
}

impl<'a> Builder<'a> {
    /// Adds a block and its buffer view; returns the view index.
    fn view(
        &mut self,
        bytes: usize,
        target: u32,
        write: impl Fn(&mut dyn Write) -> io::Result<()> + 'a,
    ) -> usize {
        self.views
            .push(json!({ "buffer": 0, "byteOffset": self.length, "byteLength": bytes, "target": target }));
        self.blocks.push(Block { write: Box::new(write) });
        self.length += bytes;
        self.views.len() - 1
    }

    fn accessor(&mut self, value: Value) -> usize {
        self.accessors.push(value);
        self.accessors.len() - 1
    }

    fn material(&mut self, name: &str, colour: [f32; 4]) -> usize {
        let mut m = json!({ "name": name, "pbrMetallicRoughness": { "baseColorFactor": colour, "metallicFactor": 0.0, "roughnessFactor": 0.9 } });
        if colour[3] < 1.0 {
            m["alphaMode"] = json!("BLEND");
        }
        self.materials.push(m);
        self.materials.len() - 1
    }

    /// A VEC3 float accessor over `points` (already Y-up), with the bounds glTF requires.
    fn positions(&mut self, points: impl Fn(usize) -> [f32; 3] + 'a, count: usize) -> usize {
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

    fn indices(&mut self, count: usize, index: impl Fn(usize) -> u32 + 'a) -> usize {
        let view = self.view(count * 4, ELEMENT_ARRAY_BUFFER, move |w| {
            (0..count).try_for_each(|i| w.write_all(&index(i).to_le_bytes()))
        });
        self.accessor(
            json!({ "bufferView": view, "componentType": UNSIGNED_INT, "count": count, "type": "SCALAR" }),
        )
    }
}

/// `karst.glb`.
pub fn write(
    folder: &mut Folder,
    frame: &Frame,
    surfaces: &Surfaces,
    net: &NetworkView,
) -> Result<(), ExportError> {
    let mut b = Builder {
        views: Vec::new(),
        accessors: Vec::new(),
        materials: Vec::new(),
        meshes: Vec::new(),
        nodes: Vec::new(),
        blocks: Vec::new(),
        length: 0,
    };
    for s in &surfaces.list {
        let mut node = json!({ "name": s.name });
        if !s.surface.triangles.is_empty() {
            let (vertices, normals, triangles) = (&s.surface.vertices, &s.normals, &s.surface.triangles);
            let position = b.positions(move |i| y_up(vertices[i]), vertices.len());
            let view = b.view(normals.len() * 12, ARRAY_BUFFER, move |w| {
                normals.iter().flat_map(|n| y_up(*n)).try_for_each(|c| w.write_all(&c.to_le_bytes()))
            });
            let normal = b.accessor(
                json!({ "bufferView": view, "componentType": FLOAT, "count": normals.len(), "type": "VEC3" }),
            );
            let indices = b.indices(triangles.len() * 3, move |i| triangles[i / 3][i % 3]);
            let material = b.material(s.name, surface_colour(s.name));
            b.meshes.push(json!({ "name": s.name, "primitives": [{ "attributes": { "POSITION": position, "NORMAL": normal }, "indices": indices, "material": material, "mode": TRIANGLES }] }));
            node["mesh"] = json!(b.meshes.len() - 1);
        }
        b.nodes.push(node);
    }
    network(&mut b, net);
    let children: Vec<usize> = (0..b.nodes.len()).collect();
    // + 0.0 turns the −0.0 of a zero origin's −y into 0.
    let translation = [0, 2, 1].map(|a| if a == 1 { -frame.origin()[a] + 0.0 } else { frame.origin()[a] });
    b.nodes.push(json!({ "name": "karst", "children": children, "translation": translation }));
    let scene_nodes = [b.nodes.len() - 1];
    let mut document = json!({
        "asset": { "version": "2.0", "generator": concat!("karstgen ", env!("CARGO_PKG_VERSION")) },
        "scene": 0,
        "scenes": [{ "name": "karst", "nodes": scene_nodes, "extras": { "origin": frame.origin(), "origin_axes": "x east, y north, z up (metres); glTF +y is z, glTF -z is y" } }],
        "nodes": b.nodes,
    });
    if b.length > 0 {
        document["meshes"] = json!(b.meshes);
        document["materials"] = json!(b.materials);
        document["accessors"] = json!(b.accessors);
        document["bufferViews"] = json!(b.views);
        document["buffers"] = json!([{ "byteLength": b.length }]);
    }
    let mut text = serde_json::to_vec(&document).map_err(|e| ExportError::Unsupported(e.to_string()))?;
    while !text.len().is_multiple_of(4) {
        text.push(b' ');
    }
    let bin = b.length.next_multiple_of(4);
    let total = 12 + 8 + text.len() + if b.length > 0 { 8 + bin } else { 0 };
    if total > u32::MAX as usize {
        return Err(ExportError::Unsupported(format!("karst.glb would be {total} bytes, over glTF's 4 GiB")));
    }
    folder.write("karst.glb", ExportFormat::Gltf, |w| {
        w.write_all(MAGIC)?;
        w.write_all(&2u32.to_le_bytes())?;
        w.write_all(&(total as u32).to_le_bytes())?;
        w.write_all(&(text.len() as u32).to_le_bytes())?;
        w.write_all(&JSON_CHUNK.to_le_bytes())?;
        w.write_all(&text)?;
        if b.length > 0 {
            w.write_all(&(bin as u32).to_le_bytes())?;
            w.write_all(&BIN_CHUNK.to_le_bytes())?;
            for block in &b.blocks {
                (block.write)(w)?;
            }
            w.write_all(&vec![0u8; bin - b.length])?;
        }
        Ok(())
    })
}

/// The `network` node: one shared position accessor, one LINES primitive per conduit type.
fn network<'a>(b: &mut Builder<'a>, net: &'a NetworkView) {
    let mut node = json!({ "name": "network" });
    let segments: Vec<_> = net.segments.iter().filter(|s| !s.is_loop()).collect();
    if !segments.is_empty() {
        let nodes = &net.nodes;
        let position = b.positions(move |i| y_up(nodes[i].position.map(|c| c as f32)), nodes.len());
        let mut primitives = Vec::new();
        for kind in ConduitType::ALL {
            let pairs: Vec<[u32; 2]> =
                segments.iter().filter(|s| s.conduit_type == kind).map(|s| s.nodes).collect();
            if pairs.is_empty() {
                continue;
            }
            let count = pairs.len() * 2;
            let indices = b.indices(count, move |i| pairs[i / 2][i % 2]);
            let material = b.material(kind.name(), type_colour(kind));
            primitives.push(json!({ "attributes": { "POSITION": position }, "indices": indices, "material": material, "mode": LINES }));
        }
        b.meshes.push(json!({ "name": "network", "primitives": primitives }));
        node["mesh"] = json!(b.meshes.len() - 1);
    }
    b.nodes.push(node);
}
