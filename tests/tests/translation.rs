//! Translation invariance (issue 16, item 0): a scene moved to projected coordinates, every
//! coordinate field shifted by a UTM-sized offset, gives the same network (nodes shifted,
//! conduits, types and zones identical), the same flows and water types, and the same metrics.
//!
//! What makes it hold: samples placed on a water table count as on it whatever the rounding of
//! their coordinates (`karst_geology::surface::ON_SURFACE`). The meshes are not compared yet:
//! they are stored as f32 world coordinates (a 0.5 m step at y ≈ 5e6), and the sdf's detail
//! noise and noise terrains are anchored at the world's origin; both wait for the local origin
//! of the artifacts (see the issue).

use std::path::Path;

use karst_artifact::{StageId, read_artifact};
use karst_pipeline::make::Selection;
use karst_skeleton::Skeleton;
use karstgen_tests::{root, run, scratch};
use toml::Value;

/// The offset: Lambert-93 / UTM magnitudes in x and y, a mountain's in z.
const OFFSET: [f64; 3] = [650_000.0, 5_100_000.0, 1_200.0];

/// The scenes moved: the presets whose fields are all planes, boxes, spheres and points. Not yet
/// `rectilinear` (its sampler, computing in world coordinates, takes another dart after 14,876
/// samples) nor `superimposed` (an amplification step picks another sample for one dead end):
/// both diverge on a comparison decided by the rounding of world coordinates, and join once
/// every stage computes relative to a local origin.
const SCENES: [&str; 5] = ["tiny", "branchwork", "looping", "karstnsim", "karstnsim-2phase"];

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

/// The scene text with every coordinate field shifted by [`OFFSET`].
fn shifted(text: &str) -> String {
    let mut scene: toml::Table = text.parse().unwrap();
    let domain = scene["domain"].as_table_mut().unwrap();
    add(domain.get_mut("min").unwrap(), &OFFSET);
    add(domain.get_mut("max").unwrap(), &OFFSET);
    let terrain = scene["terrain"].as_table_mut().unwrap();
    assert_eq!(terrain["kind"].as_str(), Some("plane"), "only plane terrains are moved here");
    shift_plane(terrain);
    if let Some(geology) = scene.get_mut("geology").and_then(Value::as_table_mut) {
        for (key, list) in geology.iter_mut() {
            for item in list.as_array_mut().into_iter().flatten() {
                let item = item.as_table_mut().unwrap();
                match key.as_str() {
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

/// The network, flows and metrics of `scene` as JSON (stages up to metrics; sdf and mesher
/// skipped).
fn network(scene: &Path, out: &Path) -> [serde_json::Value; 3] {
    for stage in [StageId::Sampling, StageId::Costgraph, StageId::Skeleton, StageId::Hydro, StageId::Metrics]
    {
        run(scene, out, &Selection { only: Some(stage), ..Selection::default() }).unwrap();
    }
    let (_, skeleton) = read_artifact::<Skeleton>(&out.join(StageId::Skeleton.file_name())).unwrap();
    let json = |stage: StageId| {
        let text = std::fs::read_to_string(out.join(stage.file_name())).unwrap();
        serde_json::from_str::<serde_json::Value>(&text).unwrap()["payload"].clone()
    };
    [serde_json::to_value(&skeleton).unwrap(), json(StageId::Hydro), json(StageId::Metrics)]
}

/// Moves the world positions of a moved scene's artifact back by the offset: node positions,
/// water levels, the lips and impact points of falls.
fn unshift(value: &mut serde_json::Value) {
    use serde_json::Value as J;
    match value {
        J::Object(map) => {
            for (k, v) in map.iter_mut() {
                match (k.as_str(), v.as_array_mut()) {
                    ("position" | "lip" | "impact", Some(p)) => {
                        for (c, o) in p.iter_mut().zip(OFFSET) {
                            *c = (c.as_f64().unwrap() - o).into();
                        }
                    }
                    ("level", Some(levels)) => {
                        for z in levels {
                            *z = (z.as_f64().unwrap() - OFFSET[2]).into();
                        }
                    }
                    _ => unshift(v),
                }
            }
        }
        J::Array(items) => items.iter_mut().for_each(unshift),
        _ => {}
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

#[test]
fn presets_moved_to_projected_coordinates_give_the_same_network_flows_and_metrics() {
    let mut failures = Vec::new();
    for name in SCENES {
        let scene = root().join(format!("fixtures/scenes/{name}.toml"));
        let out = scratch(&format!("translation-{name}"));
        let moved = out.join("moved.toml");
        std::fs::write(&moved, shifted(&std::fs::read_to_string(&scene).unwrap())).unwrap();
        let here = network(&scene, &out.join("here"));
        let mut far = network(&moved, &out.join("far"));
        for (what, (a, b)) in ["skeleton", "hydro", "metrics"].iter().zip(here.iter().zip(far.iter_mut())) {
            unshift(b);
            same_numbers(a, b, 1e-6, &format!("{name} {what}"), &mut failures);
        }
        if std::env::var_os("KARSTGEN_KEEP_TRANSLATION").is_none() {
            let _ = std::fs::remove_dir_all(&out);
        }
    }
    let scenes: std::collections::BTreeSet<String> =
        failures.iter().filter_map(|f| f.split(' ').next().map(str::to_string)).collect();
    failures.truncate(20);
    assert!(failures.is_empty(), "moved scenes differ: {scenes:?}\n{}", failures.join("\n"));
}
