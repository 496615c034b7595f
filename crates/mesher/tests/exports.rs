//! The export formats read back: OBJ through tobj, binary PLY by its header and size, and the
//! .glb container, JSON and accessors against the glTF 2.0 rules.

use karst_geology::Domain;
use karst_mesher::mesh as mesh_of;
use karst_mesher::vertex_normals;
use karst_mesher::{TriMesh, export};
use karst_sdf::{Capsule, CarvedTerrain, SdfModel, TerrainField};

fn cave() -> TriMesh {
    let domain = Domain { min: [0.0, 0.0, 0.0], max: [40.0, 30.0, 20.0] };
    let terrain = TerrainField::Plane { elevation: 15.0, origin: [0.0, 0.0], gradient: [0.02, 0.0] };
    let field = CarvedTerrain::new(SdfModel {
        capsules: vec![
            Capsule { a: [5.0, 15.0, 18.0], b: [12.0, 15.0, 8.0], radius: 2.0 },
            Capsule { a: [12.0, 15.0, 8.0], b: [35.0, 10.0, 6.0], radius: 2.5 },
        ],
        ..SdfModel::new(domain, terrain)
    });
    mesh_of(&field, 1.0, &[]).cave
}

fn temp(name: &str) -> std::path::PathBuf {
    std::env::temp_dir().join(format!("karst-mesher-{}-{name}", std::process::id()))
}

#[test]
fn obj_reads_back_with_tobj() {
    let surface = cave();
    let path = temp("cave.obj");
    export::obj::write(&path, &surface, &vertex_normals(&surface)).unwrap();
    let (models, _) =
        tobj::load_obj(&path, &tobj::LoadOptions { single_index: true, ..Default::default() }).unwrap();
    let m = &models[0].mesh;
    assert_eq!(m.positions.len(), surface.vertices.len() * 3);
    assert_eq!(m.normals.len(), surface.vertices.len() * 3);
    assert_eq!(m.indices.len(), surface.triangles.len() * 3);
    // tobj numbers vertices by first use: compare the triangles' corner positions.
    for (t, read) in surface.triangles.iter().zip(m.indices.chunks(3)).take(100) {
        for (&ours, &theirs) in t.iter().zip(read) {
            let theirs = &m.positions[3 * theirs as usize..3 * theirs as usize + 3];
            assert_eq!(theirs, surface.vertices[ours as usize]);
        }
    }
    std::fs::remove_file(path).unwrap();
}

#[test]
fn ply_has_its_header_and_exact_size() {
    let surface = cave();
    let path = temp("cave.ply");
    export::ply::write(&path, &surface, &vertex_normals(&surface)).unwrap();
    let bytes = std::fs::read(&path).unwrap();
    let end = bytes.windows(11).position(|w| w == b"end_header\n").unwrap() + 11;
    let header = std::str::from_utf8(&bytes[..end]).unwrap();
    assert!(header.starts_with("ply\nformat binary_little_endian 1.0\n"));
    assert!(header.contains(&format!("element vertex {}\n", surface.vertices.len())));
    assert!(header.contains(&format!("element face {}\n", surface.triangles.len())));
    assert_eq!(bytes.len() - end, surface.vertices.len() * 24 + surface.triangles.len() * 13);
    let first = u32::from_le_bytes(bytes[end + surface.vertices.len() * 24 + 1..][..4].try_into().unwrap());
    assert_eq!(first, surface.triangles[0][0]);
    std::fs::remove_file(path).unwrap();
}

fn u32_at(bytes: &[u8], at: usize) -> u32 {
    u32::from_le_bytes(bytes[at..at + 4].try_into().unwrap())
}

#[test]
fn glb_follows_the_container_and_accessor_rules() {
    let surface = cave();
    let glb = export::glb::encode(&surface, &vertex_normals(&surface));
    assert_eq!(&glb[..4], b"glTF");
    assert_eq!(u32_at(&glb, 4), 2);
    assert_eq!(u32_at(&glb, 8) as usize, glb.len());
    let json_len = u32_at(&glb, 12) as usize;
    assert_eq!(u32_at(&glb, 16), 0x4E4F_534A, "JSON chunk first");
    assert_eq!(json_len % 4, 0);
    let json: serde_json::Value = serde_json::from_slice(&glb[20..20 + json_len]).unwrap();
    let bin_at = 20 + json_len;
    let bin_len = u32_at(&glb, bin_at) as usize;
    assert_eq!(u32_at(&glb, bin_at + 4), 0x004E_4942, "BIN chunk second");
    assert_eq!(bin_at + 8 + bin_len, glb.len());
    let bin = &glb[bin_at + 8..];
    assert_eq!(json["asset"]["version"], "2.0");
    assert_eq!(json["buffers"][0]["byteLength"].as_u64().unwrap() as usize, bin_len);
    for view in json["bufferViews"].as_array().unwrap() {
        let end = view["byteOffset"].as_u64().unwrap() + view["byteLength"].as_u64().unwrap();
        assert!(end as usize <= bin_len);
        assert_eq!(view["byteOffset"].as_u64().unwrap() % 4, 0);
    }
    let accessors = json["accessors"].as_array().unwrap();
    let n = surface.vertices.len() as u64;
    let primitive = &json["meshes"][0]["primitives"][0];
    let position = &accessors[primitive["attributes"]["POSITION"].as_u64().unwrap() as usize];
    let indices = &accessors[primitive["indices"].as_u64().unwrap() as usize];
    assert_eq!(position["count"].as_u64().unwrap(), n);
    assert_eq!(indices["count"].as_u64().unwrap(), surface.triangles.len() as u64 * 3);
    for accessor in accessors {
        let view = &json["bufferViews"][accessor["bufferView"].as_u64().unwrap() as usize];
        let size = if accessor["type"] == "VEC3" { 12 } else { 4 };
        assert!(accessor["count"].as_u64().unwrap() * size <= view["byteLength"].as_u64().unwrap());
    }
    // POSITION min/max are exact bounds of the data (glTF requires them).
    let offset = json["bufferViews"][position["bufferView"].as_u64().unwrap() as usize]["byteOffset"]
        .as_u64()
        .unwrap();
    let floats: Vec<f32> = (0..n as usize * 3)
        .map(|i| f32::from_le_bytes(bin[offset as usize + 4 * i..][..4].try_into().unwrap()))
        .collect();
    for axis in 0..3 {
        let values = floats.iter().skip(axis).step_by(3);
        let min = values.clone().copied().fold(f32::INFINITY, f32::min);
        let max = values.copied().fold(f32::NEG_INFINITY, f32::max);
        assert_eq!(position["min"][axis].as_f64().unwrap() as f32, min);
        assert_eq!(position["max"][axis].as_f64().unwrap() as f32, max);
    }
    let index_view = &json["bufferViews"][indices["bufferView"].as_u64().unwrap() as usize];
    let start = index_view["byteOffset"].as_u64().unwrap() as usize;
    assert!((0..surface.triangles.len() * 3).all(|i| (u32_at(bin, start + 4 * i) as u64) < n));
    // Y-up: the scene's z is glTF's y.
    assert_eq!(floats[1], surface.vertices[0][2]);
    assert_eq!(floats[2], -surface.vertices[0][1]);
}
