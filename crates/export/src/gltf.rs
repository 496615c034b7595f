//! Binary glTF 2.0 (`karst.glb`: Blender, three.js, game engines; checked by the Khronos
//! glTF-Validator): one scene whose nodes are named `terrain`, `cave`, `water` (the chosen
//! surfaces, triangles with normals) and `network` (the conduit segments as line primitives,
//! one per conduit type, each with a material named and coloured after its type). Laid out and
//! written by the shared glTF writer (`karst-gltf`).
//!
//! A file for viewers, not an archive: when the full surfaces would make it larger than its
//! bound (`export.gltf_max_mb`, 100 MB by default), they are simplified by meshoptimizer
//! ([`karst_gltf::simplify`]: closed surfaces stay closed, open borders stay put) to the
//! triangles the bound allows, each surface keeping the same share of its triangles; the
//! surface's node says so in its `extras` (full and kept triangles, the error in metres).
//! `export.gltf_full = true` writes the full mesh whatever its size.
//!
//! glTF is Y-up, the scene Z-up: positions and normals are turned by −90° about x,
//! (x, y, z) → (x, z, −y), a rotation, so winding and orientation are kept. Positions are
//! single-precision local coordinates (sub-millimetre within a few kilometres of the origin);
//! the four nodes are the children of a root node `karst` translated by the world position of
//! the local origin (turned Y-up, written as JSON numbers, i.e. in f64), so that a viewer
//! places the model at its world coordinates; the scene's `extras.origin` holds the same origin
//! z up. The file is streamed: the JSON chunk is built from the counts, then every buffer goes
//! straight from the arrays to the file.

use std::borrow::Cow;

use rayon::prelude::*;
use serde_json::json;

use karst_gltf::simplify;
use karst_gltf::{Gltf, LINES, TRIANGLES, y_up};
use karst_mesher::TriMesh;
use karst_scene::params::ExportFormat;
use karst_skeleton::ConduitType;

use crate::ExportError;
use crate::folder::{Folder, Surfaces, unit_normals};
use crate::frame::Frame;
use crate::network::NetworkView;

/// Bytes of the JSON chunk and headers, an upper bound for the few dozen objects of the file.
const DOCUMENT_BYTES: f64 = 16384.0;
/// Bytes per vertex (position and normal, f32) and per triangle (three u32 indices).
const VERTEX_BYTES: f64 = 24.0;
const TRIANGLE_BYTES: f64 = 12.0;
/// Simplification passes at most: each corrects the triangle share by the bytes the last gave.
const PASSES: usize = 4;
/// The first pass aims this share of the room: a simplified surface keeps a little more than
/// its share of the vertices (on the 6 km case 0.01 % too many bytes at the exact share), and
/// a second pass would simplify every surface again (1.5 s of the export's 4 there).
const FIRST_AIM: f64 = 0.99;

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

fn network_bytes(net: &NetworkView) -> f64 {
    12.0 * net.nodes.len() as f64 + 8.0 * net.segments.len() as f64
}

/// One surface as the file holds it: the mesh's own arrays, or a simplified copy.
struct Shown<'a> {
    name: &'static str,
    vertices: Cow<'a, [[f32; 3]]>,
    normals: Cow<'a, [[f32; 3]]>,
    triangles: Cow<'a, [[u32; 3]]>,
    /// The full surface's triangles and the simplification's error (metres), when simplified.
    simplified: Option<(usize, f64)>,
}

impl Shown<'_> {
    fn bytes(&self) -> f64 {
        self.vertices.len() as f64 * VERTEX_BYTES + self.triangles.len() as f64 * TRIANGLE_BYTES
    }
}

/// The surfaces at full resolution when they fit in `bound` bytes (or `bound` is `None`),
/// otherwise simplified, each to the same share of its triangles, so that the file fits.
fn shown<'a>(surfaces: &'a Surfaces, net: &NetworkView, bound: Option<f64>) -> Vec<Shown<'a>> {
    let full: Vec<Shown> = surfaces
        .list
        .iter()
        .map(|s| Shown {
            name: s.name,
            vertices: Cow::Borrowed(&s.surface.vertices),
            normals: Cow::Borrowed(&s.normals),
            triangles: Cow::Borrowed(&s.surface.triangles),
            simplified: None,
        })
        .collect();
    let Some(bound) = bound else { return full };
    let room = (bound - DOCUMENT_BYTES - network_bytes(net)).max(0.0);
    let full_bytes: f64 = full.iter().map(Shown::bytes).sum();
    if full_bytes <= room {
        return full;
    }
    let mut share = FIRST_AIM * room / full_bytes;
    let mut kept = Vec::new();
    for _ in 0..PASSES {
        // The surfaces side by side: each is simplified on its own, in the same order.
        kept = surfaces.list.par_iter().map(|s| simplified(s.name, s.surface, share)).collect();
        let kept_bytes: f64 = kept.iter().map(Shown::bytes).sum();
        if kept_bytes <= room {
            break;
        }
        share *= 0.98 * room / kept_bytes;
    }
    kept
}

/// `surface` reduced to `share` of its triangles, with its normals computed again.
fn simplified<'a>(name: &'static str, surface: &TriMesh, share: f64) -> Shown<'a> {
    let target = (surface.triangles.len() as f64 * share).floor() as usize;
    let s = simplify::to_triangles(&surface.vertices, &surface.triangles, target);
    let mesh = TriMesh { vertices: s.positions, triangles: s.triangles, ..TriMesh::default() };
    let normals = unit_normals(&mesh);
    let extent = extent(&surface.vertices);
    Shown {
        name,
        normals: Cow::Owned(normals),
        simplified: Some((surface.triangles.len(), f64::from(s.relative_error) * extent)),
        vertices: Cow::Owned(mesh.vertices),
        triangles: Cow::Owned(mesh.triangles),
    }
}

/// The longest side of the box around `points`: meshoptimizer's errors are relative to it.
fn extent(points: &[[f32; 3]]) -> f64 {
    let (mut min, mut max) = ([f32::INFINITY; 3], [f32::NEG_INFINITY; 3]);
    for p in points {
        for a in 0..3 {
            min[a] = min[a].min(p[a]);
            max[a] = max[a].max(p[a]);
        }
    }
    (0..3).map(|a| f64::from(max[a] - min[a])).fold(0.0, f64::max)
}

/// `karst.glb`, within `bound` bytes when one is given (simplified surfaces).
pub fn write(
    folder: &mut Folder,
    frame: &Frame,
    surfaces: &Surfaces,
    net: &NetworkView,
    bound: Option<f64>,
) -> Result<(), ExportError> {
    let shown = shown(surfaces, net, bound);
    let mut b = Gltf::new();
    for s in &shown {
        let mut node = json!({ "name": s.name });
        if !s.triangles.is_empty() {
            let (vertices, normals, triangles) = (&s.vertices, &s.normals, &s.triangles);
            let position = b.positions(move |i| y_up(vertices[i]), vertices.len());
            let normal = b.directions(move |i| y_up(normals[i]), normals.len());
            let indices = b.indices(triangles.len() * 3, move |i| triangles[i / 3][i % 3]);
            let material = b.material(s.name, surface_colour(s.name));
            let mesh = b.mesh(json!({ "name": s.name, "primitives": [{ "attributes": { "POSITION": position, "NORMAL": normal }, "indices": indices, "material": material, "mode": TRIANGLES }] }));
            node["mesh"] = json!(mesh);
        }
        if let Some((full, error)) = s.simplified {
            node["extras"] = json!({ "simplified": { "full_triangles": full, "triangles": s.triangles.len(), "error_m": error } });
        }
        b.node(node);
    }
    network(&mut b, net);
    let children: Vec<usize> = (0..=shown.len()).collect();
    // + 0.0 turns the −0.0 of a zero origin's −y into 0.
    let translation = [0, 2, 1].map(|a| if a == 1 { -frame.origin()[a] + 0.0 } else { frame.origin()[a] });
    let root = b.node(json!({ "name": "karst", "children": children, "translation": translation }));
    let scenes = json!([{ "name": "karst", "nodes": [root], "extras": { "origin": frame.origin(), "origin_axes": "x east, y north, z up (metres); glTF +y is z, glTF -z is y" } }]);
    let glb = b
        .finish(concat!("karstgen ", env!("CARGO_PKG_VERSION")), scenes)
        .map_err(|e| ExportError::Unsupported(format!("karst.glb: {e}")))?;
    folder.write("karst.glb", ExportFormat::Gltf, |w| glb.write_to(w))
}

/// The `network` node: one shared position accessor, one LINES primitive per conduit type.
fn network<'a>(b: &mut Gltf<'a>, net: &'a NetworkView) {
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
        node["mesh"] = json!(b.mesh(json!({ "name": "network", "primitives": primitives })));
    }
    b.node(node);
}
