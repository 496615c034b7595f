//! Translation invariance (issue 16, item 0): a scene moved to projected coordinates, every
//! coordinate field shifted by a UTM-sized offset, gives the same network (conduits, types and
//! zones identical), the same flows and water types, the same metrics and the same meshes (same
//! triangles, vertices within 1 mm), and its artifacts record the moved origin.
//!
//! What makes it hold: a scene is localized when loaded (every coordinate relative to the
//! domain's `min` corner, `karst_scene::Scene::origin`), so every stage computes on the same
//! small numbers whatever the offset; what is left of the offset is the rounding of the moved
//! file's decimals (1e-10 m), which cannot move a sample off a water table
//! (`karst_geology::surface::ON_SURFACE`).

use std::path::Path;

use karst_artifact::{StageId, read_artifact, read_header};
use karst_mesher::Mesh;
use karst_pipeline::make::Selection;
use karst_skeleton::Skeleton;
use karstgen_tests::{root, run, scratch};
use toml::Value;

/// The offset: Lambert-93 / UTM magnitudes in x and y, a mountain's in z.
const OFFSET: [f64; 3] = [650_000.0, 5_100_000.0, 1_200.0];

fn add(value: &mut Value, offset: &[f64]) {
    if let Some(items) = value.as_array_mut() {
        for (v, o) in items.iter_mut().zip(offset) {
            *v = Value::Float(v.as_float().or(v.as_integer().map(|i| i as f64)).unwrap() + o);
        }
    }
}

fn add_z(value: &mut Value) {
    if let Some(z) = value.as_float().or(value.as_integer().map(|i| i as f64)) {
        *value = Value::Float(z + OFFSET[2]);
    }
}

/// A plane's `origin` (default [0, 0]) and `elevation`, shifted.
fn shift_plane(table: &mut toml::Table) {
    let origin = table.entry("origin").or_insert(Value::Array(vec![Value::Float(0.0), Value::Float(0.0)]));
    add(origin, &OFFSET[..2]);
    if let Some(e) = table.get_mut("elevation") {
        add_z(e);
    }
}

/// A TSurf moved by [`OFFSET`]: its `VRTX id x y z` lines shifted.
fn shifted_tsurf(text: &str) -> String {
    let line = |l: &str| {
        let fields: Vec<&str> = l.split_whitespace().collect();
        if fields.len() == 5 && (fields[0] == "VRTX" || fields[0] == "PVRTX") {
            let c = |i: usize| fields[i + 2].parse::<f64>().unwrap() + OFFSET[i];
            format!("{} {} {:?} {:?} {:?}", fields[0], fields[1], c(0), c(1), c(2))
        } else {
            l.to_string()
        }
    };
    text.lines().map(line).collect::<Vec<_>>().join("\n") + "\n"
}

/// The scene text with every coordinate field shifted by [`OFFSET`]; TIN surfaces are
/// written moved into `dir`.
fn shifted(text: &str, dir: &Path) -> String {
    let mut scene: toml::Table = text.parse().unwrap();
    let domain = scene["domain"].as_table_mut().unwrap();
    add(domain.get_mut("min").unwrap(), &OFFSET);
    add(domain.get_mut("max").unwrap(), &OFFSET);
    let terrain = scene["terrain"].as_table_mut().unwrap();
    match terrain["kind"].as_str() {
        Some("plane") => shift_plane(terrain),
        // Noise is defined in the local frame: only its mean elevation moves.
        Some("noise") => add_z(terrain.get_mut("elevation").unwrap()),
        Some("heightfield") => {
            add(terrain.get_mut("origin").unwrap(), &OFFSET[..2]);
            let offset = terrain.entry("offset").or_insert(Value::Float(0.0));
            add_z(offset);
        }
        kind => panic!("terrain kind {kind:?} is not moved here"),
    }
    if let Some(geology) = scene.get_mut("geology").and_then(Value::as_table_mut) {
        for (key, list) in geology.iter_mut() {
            for item in list.as_array_mut().into_iter().flatten() {
                let item = item.as_table_mut().unwrap();
                match key.as_str() {
                    "water_tables" | "horizons" | "faults" if item.contains_key("file") => {
                        let file = item["file"].as_str().unwrap();
                        let tsurf =
                            std::fs::read_to_string(root().join("fixtures/scenes").join(file)).unwrap();
                        let moved = dir.join(Path::new(file).file_name().unwrap());
                        std::fs::write(&moved, shifted_tsurf(&tsurf)).unwrap();
                        item.insert("file".into(), Value::String(moved.display().to_string()));
                    }
                    "water_tables" | "horizons" | "faults" => shift_plane(item),
                    "fractures" => {}
                    _ => {
                        for field in ["centre", "min", "max"] {
                            if let Some(v) = item.get_mut(field) {
                                add(v, &OFFSET);
                            }
                        }
                        for field in ["top", "bottom"] {
                            if let Some(v) = item.get_mut(field) {
                                add_z(v);
                            }
                        }
                    }
                }
            }
        }
    }
    for k in scene.get_mut("keypoints").and_then(Value::as_array_mut).into_iter().flatten() {
        add(k.get_mut("position").unwrap(), &OFFSET);
    }
    for pool in scene
        .get_mut("hydro")
        .and_then(|h| h.get_mut("pools"))
        .and_then(Value::as_array_mut)
        .into_iter()
        .flatten()
    {
        add(pool.get_mut("at").unwrap(), &OFFSET);
        for outlet in pool.get_mut("outlets").and_then(Value::as_array_mut).into_iter().flatten() {
            add(outlet.get_mut("towards").unwrap(), &OFFSET);
        }
    }
    toml::to_string(&scene).unwrap()
}

/// The scene, moved or not, written into the scratch folder: meshes at 8 m (terrain) and 2 m
/// (cave, water), so that every preset meshes in seconds (the frame, not the resolution, is
/// under test), and its data file named absolutely.
fn prepared(name: &str, text: &str) -> String {
    let mut scene: toml::Table = text.parse().unwrap();
    let mesher = scene.entry("mesher").or_insert(Value::Table(toml::Table::new())).as_table_mut().unwrap();
    mesher.insert("cell_size".into(), Value::Float(8.0));
    // The layered scene's thin conduits fall between 2 m cells, and an empty cave mesh is
    // refused by the mesher.
    let cave_cell_size = if name == "layered" { 1.0 } else { 2.0 };
    mesher.insert("cave_cell_size".into(), Value::Float(cave_cell_size));
    let absolute = |item: &mut toml::Table| {
        if let Some(file) = item.get("file").and_then(Value::as_str) {
            let absolute = root().join("fixtures/scenes").join(file).display().to_string();
            item.insert("file".into(), Value::String(absolute));
        }
    };
    absolute(scene["terrain"].as_table_mut().unwrap());
    for (_, list) in scene.get_mut("geology").and_then(Value::as_table_mut).into_iter().flatten() {
        for item in list.as_array_mut().into_iter().flatten() {
            absolute(item.as_table_mut().unwrap());
        }
    }
    toml::to_string(&scene).unwrap()
}

/// The network, flows and metrics of `scene` as JSON, and its meshes (every stage but the
/// export).
fn outputs(scene: &Path, out: &Path) -> ([serde_json::Value; 3], Mesh) {
    for stage in &StageId::ALL[..StageId::Export as usize] {
        run(scene, out, &Selection { only: Some(*stage), ..Selection::default() }).unwrap();
    }
    let (_, skeleton) = read_artifact::<Skeleton>(&out.join(StageId::Skeleton.file_name())).unwrap();
    let json = |stage: StageId| {
        let text = std::fs::read_to_string(out.join(stage.file_name())).unwrap();
        serde_json::from_str::<serde_json::Value>(&text).unwrap()["payload"].clone()
    };
    let (_, mesh) = read_artifact::<Mesh>(&out.join(StageId::Mesher.file_name())).unwrap();
    ([serde_json::to_value(&skeleton).unwrap(), json(StageId::Hydro), json(StageId::Metrics)], mesh)
}

/// The same triangles, and vertices within 1 mm (both local).
fn same_meshes(name: &str, a: &Mesh, b: &Mesh, failures: &mut Vec<String>) {
    for ((surface, x), (_, y)) in a.surfaces().into_iter().zip(b.surfaces()) {
        if x.triangles != y.triangles || x.vertices.len() != y.vertices.len() {
            failures.push(format!(
                "{name} mesh: {surface}: {} vs {} triangles, {} vs {} vertices, triangles differ",
                x.triangles.len(),
                y.triangles.len(),
                x.vertices.len(),
                y.vertices.len()
            ));
            continue;
        }
        let farthest = x
            .vertices
            .iter()
            .zip(&y.vertices)
            .map(|(p, q)| (0..3).map(|i| (p[i] - q[i]).abs()).fold(0.0f32, f32::max))
            .fold(0.0f32, f32::max);
        if farthest > 1e-3 {
            failures.push(format!("{name} mesh: {surface}: a vertex moved by {farthest} m"));
        }
    }
}

/// Every number of `a` and `b` equal within `tolerance` (relative), every other value equal.
fn same_numbers(
    a: &serde_json::Value,
    b: &serde_json::Value,
    tolerance: f64,
    at: &str,
    failures: &mut Vec<String>,
) {
    use serde_json::Value as J;
    match (a, b) {
        (J::Number(x), J::Number(y)) => {
            let (x, y) = (x.as_f64().unwrap(), y.as_f64().unwrap());
            if (x - y).abs() > tolerance * x.abs().max(1.0) {
                failures.push(format!("{at}: {x} vs {y}"));
            }
        }
        (J::Array(x), J::Array(y)) if x.len() == y.len() => {
            for (i, (x, y)) in x.iter().zip(y).enumerate() {
                same_numbers(x, y, tolerance, &format!("{at}[{i}]"), failures);
            }
        }
        (J::Object(x), J::Object(y)) if x.len() == y.len() => {
            for (k, v) in x {
                match y.get(k) {
                    Some(w) => same_numbers(v, w, tolerance, &format!("{at}.{k}"), failures),
                    None => failures.push(format!("{at}.{k}: missing")),
                }
            }
        }
        _ if a == b => {}
        _ => {
            let short = |v: &serde_json::Value| v.to_string().chars().take(120).collect::<String>();
            failures.push(format!("{at}: {} vs {}", short(a), short(b)))
        }
    }
}

/// Runs the preset `name` here and moved by [`OFFSET`] and compares everything.
fn moved_preset_is_the_same(name: &str) {
    let scene = root().join(format!("fixtures/scenes/{name}.toml"));
    let text = std::fs::read_to_string(&scene).unwrap();
    let out = scratch(&format!("translation-{name}"));
    let (near, moved) = (out.join("here.toml"), out.join("moved.toml"));
    std::fs::write(&near, prepared(name, &text)).unwrap();
    std::fs::write(&moved, prepared(name, &shifted(&text, &out))).unwrap();
    let (here, here_mesh) = outputs(&near, &out.join("here"));
    let (far, far_mesh) = outputs(&moved, &out.join("far"));
    let mut failures = Vec::new();
    for (what, (a, b)) in ["skeleton", "hydro", "metrics"].iter().zip(here.iter().zip(far.iter())) {
        same_numbers(a, b, 1e-6, &format!("{name} {what}"), &mut failures);
    }
    same_meshes(name, &here_mesh, &far_mesh, &mut failures);
    for stage in &StageId::ALL[..StageId::Export as usize] {
        let header = read_header(&out.join("far").join(stage.file_name())).unwrap();
        if header.origin != OFFSET {
            failures.push(format!("{name} {}: origin {:?}", stage.name(), header.origin));
        }
    }
    if failures.is_empty() || std::env::var_os("KARSTGEN_KEEP_TRANSLATION").is_none() {
        let _ = std::fs::remove_dir_all(&out);
    }
    failures.truncate(20);
    assert!(failures.is_empty(), "{name} moved by {OFFSET:?} differs:\n{}", failures.join("\n"));
}

/// One test per preset: every scene of fixtures/scenes but geotiff (already in Lambert-93) and
/// waterfall. The waterfall's PNG heightfield has elevations offset + 0.01·value: moved, they are
/// (1200 + 0.01·value) − 1200, which differs from 0.01·value by up to 1e-13 m, and one Poisson
/// dart of its 17,466 lying that close to the cliff's surface flips (the same network, one
/// sample index shifted). Exact translation of PNG heightfields needs the grid to keep its
/// offset apart from the scaled values (a schema change of sdf.bin): not done yet.
macro_rules! presets {
    ($($test:ident => $name:literal,)*) => {
        $(
            #[test]
            fn $test() {
                moved_preset_is_the_same($name);
            }
        )*

        #[test]
        fn every_preset_is_moved() {
            let tested = [$($name),*];
            for entry in std::fs::read_dir(root().join("fixtures/scenes")).unwrap() {
                let path = entry.unwrap().path();
                let stem = path.file_stem().unwrap().to_string_lossy().into_owned();
                if path.extension().is_some_and(|e| e == "toml") && stem != "geotiff" && stem != "waterfall" {
                    assert!(tested.contains(&stem.as_str()), "{stem} is not moved in translation.rs");
                }
            }
        }
    };
}

presets! {
    tiny_moved => "tiny",
    branchwork_moved => "branchwork",
    looping_moved => "looping",
    karstnsim_moved => "karstnsim",
    karstnsim_2phase_moved => "karstnsim-2phase",
    rectilinear_moved => "rectilinear",
    superimposed_moved => "superimposed",
    layered_moved => "layered",
    default_moved => "default",
}
