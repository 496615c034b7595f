//! A scene in Lambert-93 (EPSG:2154) through every stage and every export format: a key point
//! at (651234.567, 6862345.678) comes back from every network format within 1 mm, and every
//! mesh format's vertices are the mesh's local f32 vertices plus the run's origin within 1 mm
//! (issue 16's precision budget). The artifacts hold local coordinates (origin = the domain's
//! min corner, recorded in their headers); the exports add the origin back.

mod common;

use std::path::Path;

use common::{python_json, scratch};
use karst_artifact::{StageId, read_artifact, read_header};
use karst_mesher::Mesh;
use karst_pipeline::make::{self, Selection};
use karst_pipeline::scene::SceneFile;
use karst_skeleton::Skeleton;

/// The key point, world coordinates.
const SINK: [f64; 3] = [651_234.567, 6_862_345.678, 449.25];
const ORIGIN: [f64; 3] = [651_000.0, 6_862_000.0, 250.0];

const SCENE: &str = r#"name = "lambert"
seed = 7
crs = "EPSG:2154"

[domain]
min = [651000.0, 6862000.0, 250.0]
max = [651500.0, 6862500.0, 500.0]

[terrain]
kind = "plane"
elevation = 450.0
origin = [651000.0, 6862000.0]

[[geology.water_tables]]
name = "wt"
elevation = 320.0
origin = [651000.0, 6862000.0]

[[keypoints]]
name = "gouffre"
kind = "sink"
position = [651234.567, 6862345.678, 449.25]

[[keypoints]]
name = "source"
kind = "spring"
position = [651450.0, 6862050.0, 320.0]
water_table = "wt"

[sampling]
radius = 20.0

[mesher]
cell_size = 8.0
cave_cell_size = 2.0

[export]
formats = ["vtk", "vtk-meshes", "gocad", "gocad-meshes", "survex", "swmm", "gltf", "obj", "ply", "csv"]
"#;

fn close(what: &str, found: [f64; 3], expected: [f64; 3]) {
    let off = (0..3).map(|a| (found[a] - expected[a]).abs()).fold(0.0, f64::max);
    assert!(off <= 1e-3, "{what}: {found:?} is {off} m from {expected:?}");
}

fn numbers(fields: &[&str]) -> Vec<f64> {
    fields.iter().map(|f| f.parse().unwrap()).collect()
}

/// The line of `text` whose whitespace-separated fields satisfy `pick`, as its fields.
fn line(text: &str, pick: impl Fn(&[&str]) -> bool) -> Vec<&str> {
    text.lines()
        .map(|l| l.split_whitespace().collect::<Vec<_>>())
        .find(|f| pick(f))
        .unwrap_or_else(|| panic!("no such line"))
}

/// The local vertices of the glb's mesh named `mesh` (Y-up f32) and the root's translation.
fn glb_positions(file: &Path, mesh: &str) -> (Vec<[f32; 3]>, [f64; 3]) {
    let bytes = std::fs::read(file).unwrap();
    let json_len = u32::from_le_bytes(bytes[12..16].try_into().unwrap()) as usize;
    let doc: serde_json::Value = serde_json::from_slice(&bytes[20..20 + json_len]).unwrap();
    let bin = &bytes[20 + json_len + 8..];
    let meshes = doc["meshes"].as_array().unwrap();
    let m = meshes.iter().find(|m| m["name"] == mesh).unwrap();
    let accessor = &doc["accessors"][m["primitives"][0]["attributes"]["POSITION"].as_u64().unwrap() as usize];
    let view = &doc["bufferViews"][accessor["bufferView"].as_u64().unwrap() as usize];
    let start = view["byteOffset"].as_u64().unwrap_or(0) as usize;
    let count = accessor["count"].as_u64().unwrap() as usize;
    let f = |i: usize| f32::from_le_bytes(bin[start + 4 * i..start + 4 * i + 4].try_into().unwrap());
    let positions = (0..count).map(|v| [f(3 * v), f(3 * v + 1), f(3 * v + 2)]).collect();
    let root = doc["nodes"].as_array().unwrap().iter().find(|n| n["name"] == "karst").unwrap();
    let t: Vec<f64> = root["translation"].as_array().unwrap().iter().map(|v| v.as_f64().unwrap()).collect();
    (positions, [t[0], t[1], t[2]])
}

/// World (z up) of a glTF local Y-up position under a Y-up translation.
fn glb_world(p: [f32; 3], t: [f64; 3]) -> [f64; 3] {
    let y_up = [f64::from(p[0]) + t[0], f64::from(p[1]) + t[1], f64::from(p[2]) + t[2]];
    [y_up[0], -y_up[2], y_up[1]]
}

#[test]
fn a_lambert_93_key_point_comes_back_from_every_export_within_a_millimetre() {
    let dir = scratch("georeferenced");
    let scene_path = dir.join("lambert.toml");
    std::fs::write(&scene_path, SCENE).unwrap();
    let out = dir.join("out");
    make::run(&SceneFile::load(&scene_path).unwrap(), &out, &Selection::default(), &mut |_| {})
        .unwrap_or_else(|e| panic!("{e}"));
    for stage in StageId::ALL {
        let header = read_header(&out.join(stage.file_name())).unwrap();
        assert_eq!((header.origin, header.crs.as_deref()), (ORIGIN, Some("EPSG:2154")), "{}", stage.name());
    }
    let (_, skeleton) = read_artifact::<Skeleton>(&out.join("skeleton.json")).unwrap();
    let node = skeleton.nodes.iter().position(|n| n.keypoint.as_deref() == Some("gouffre")).unwrap();
    let id = (node + 1).to_string();
    // The artifacts are local.
    close(
        "skeleton.json (local)",
        skeleton.nodes[node].position,
        std::array::from_fn(|a| SINK[a] - ORIGIN[a]),
    );
    let export = out.join("export");
    let read = |name: &str| std::fs::read_to_string(export.join(name)).unwrap();

    let svx = read("network.svx");
    let fix = line(&svx, |f| f.len() >= 5 && f[0] == "*fix" && f[1] == id);
    close("network.svx *fix", numbers(&fix[2..5]).try_into().unwrap(), SINK);

    let pl = read("network.pl");
    let pvrtx = line(&pl, |f| f.len() >= 6 && f[0] == "PVRTX" && f[5] == id);
    close("network.pl PVRTX", numbers(&pvrtx[2..5]).try_into().unwrap(), SINK);

    let inp = read("network.inp");
    let coordinates = &inp[inp.find("[COORDINATES]").unwrap()..];
    let xy = line(coordinates, |f| f.len() == 3 && f[0] == id);
    let xy = numbers(&xy[1..3]);
    close("network.inp [COORDINATES]", [xy[0], xy[1], SINK[2]], SINK);

    let csv = read("nodes.csv");
    let row: Vec<&str> = csv.lines().map(|l| l.split(',').collect::<Vec<_>>()).find(|r| r[0] == id).unwrap();
    close("nodes.csv", numbers(&row[1..4]).try_into().unwrap(), SINK);

    let vtp = export.join("network.vtp");
    let report = python_json("read_vtp.py", &[vtp.to_str().unwrap(), "--points"]);
    let p: Vec<f64> =
        report["points_all"][node].as_array().unwrap().iter().map(|v| v.as_f64().unwrap()).collect();
    close("network.vtp", p.try_into().unwrap(), SINK);

    let (network, translation) = glb_positions(&export.join("karst.glb"), "network");
    close("karst.glb network", glb_world(network[node], translation), SINK);

    // Mesh formats: every cave vertex at the mesh's local vertex + the origin.
    let (_, mesh) = read_artifact::<Mesh>(&out.join("mesh.bin")).unwrap();
    let world: Vec<[f64; 3]> =
        mesh.cave.vertices.iter().map(|v| std::array::from_fn(|a| f64::from(v[a]) + ORIGIN[a])).collect();
    assert!(!world.is_empty());
    let obj: Vec<Vec<f64>> = read("cave.obj")
        .lines()
        .filter_map(|l| l.strip_prefix("v "))
        .map(|l| numbers(&l.split_whitespace().collect::<Vec<_>>()))
        .collect();
    let ts: Vec<Vec<f64>> = read("cave.ts")
        .lines()
        .map(|l| l.split_whitespace().collect::<Vec<_>>())
        .filter(|f| f.first().is_some_and(|k| *k == "VRTX" || *k == "PVRTX"))
        .map(|f| numbers(&f[2..5]))
        .collect();
    let ply = std::fs::read(export.join("cave.ply")).unwrap();
    let body = &ply[ply.windows(11).position(|w| w == b"end_header\n").unwrap() + 11..];
    let stride = 3 * 8 + 3 * 4;
    let ply_vertex = |i: usize| -> [f64; 3] {
        std::array::from_fn(|a| {
            let at = i * stride + 8 * a;
            f64::from_le_bytes(body[at..at + 8].try_into().unwrap())
        })
    };
    let (glb, translation) = glb_positions(&export.join("karst.glb"), "cave");
    let cave_vtp = export.join("cave.vtp");
    let vtp_points = python_json("read_vtp.py", &[cave_vtp.to_str().unwrap(), "--points"]);
    for (i, expected) in world.iter().enumerate().step_by(97) {
        close("cave.obj", obj[i].clone().try_into().unwrap(), *expected);
        close("cave.ts", ts[i].clone().try_into().unwrap(), *expected);
        close("cave.ply", ply_vertex(i), *expected);
        close("karst.glb cave", glb_world(glb[i], translation), *expected);
        let p: Vec<f64> =
            vtp_points["points_all"][i].as_array().unwrap().iter().map(|v| v.as_f64().unwrap()).collect();
        close("cave.vtp", p.try_into().unwrap(), *expected);
    }
    assert_eq!((obj.len(), ts.len()), (world.len(), world.len()));
    let _ = std::fs::remove_dir_all(&dir);
}
