//! Writing a view from the tiny scene's golden artifacts: what it holds, that it is the same
//! whatever the number of threads, and what happens when the folder is not a run or a stage
//! is missing or corrupted.

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

use karst_pipeline::ensemble;
use karst_pipeline::scene::SceneFile;
use karst_view::{ViewError, write_view};
use serde_json::Value;

use karst_testkit::{Scratch, root, scratch};

/// A scratch copy of the tiny scene's golden run, without the files named in `drop`.
fn tiny_run(name: &str, drop: &[&str]) -> Scratch {
    let dir = scratch(name);
    for entry in std::fs::read_dir(root().join("fixtures/golden/tiny")).unwrap() {
        let path = entry.unwrap().path();
        let file = path.file_name().unwrap().to_str().unwrap().to_string();
        if !drop.contains(&file.as_str()) {
            std::fs::copy(&path, dir.join(&file)).unwrap();
        }
    }
    dir
}

fn tiny_scene() -> PathBuf {
    root().join("fixtures/scenes/tiny.toml")
}

fn run_json(dir: &Path) -> Value {
    serde_json::from_slice(&std::fs::read(dir.join("view/data/run.json")).unwrap()).unwrap()
}

/// Every file under `dir` with its bytes.
fn files(dir: &Path, prefix: &str, out: &mut BTreeMap<String, Vec<u8>>) {
    for entry in std::fs::read_dir(dir).unwrap() {
        let path = entry.unwrap().path();
        let name = format!("{prefix}{}", path.file_name().unwrap().to_string_lossy());
        if path.is_dir() {
            files(&path, &format!("{name}/"), out);
        } else {
            out.insert(name, std::fs::read(&path).unwrap());
        }
    }
}

#[test]
fn a_complete_run_gives_every_layer() {
    let dir = tiny_run("complete", &[]);
    let report = write_view(&dir, Some(&tiny_scene())).unwrap();
    assert!(report.problems.is_empty(), "{:?}", report.problems);
    let data = run_json(&dir);
    assert_eq!(data["format"], "karstgen-view");
    let skeleton: Value = serde_json::from_slice(&std::fs::read(dir.join("skeleton.json")).unwrap()).unwrap();
    let conduits = skeleton["payload"]["conduits"].as_array().unwrap().len();
    assert!(conduits > 1);
    assert_eq!(data["skeleton"]["conduits"].as_array().unwrap().len(), conduits);
    assert_eq!(data["hydro"]["conduits"].as_array().unwrap().len(), conduits);
    assert_eq!(data["domain"]["max"], serde_json::json!([200.0, 150.0, 60.0]));
    // The surface streams: every segment of streams.json with its type and its two ends.
    let streams: Value = serde_json::from_slice(&std::fs::read(dir.join("streams.json")).unwrap()).unwrap();
    let (shown, written) =
        (data["streams"]["segments"].as_array().unwrap(), streams["payload"]["segments"].as_array().unwrap());
    assert_eq!(shown.len(), written.len());
    for (v, g) in shown.iter().zip(written) {
        assert_eq!(v["water"], g["water"]);
        let ends = [&g["from"], &g["to"]]
            .map(|n| &streams["payload"]["nodes"][n.as_u64().unwrap() as usize]["position"]);
        assert_eq!(v["points"], serde_json::json!(ends));
    }
    let kinds: Vec<(&str, &str)> = data["keypoints"]
        .as_array()
        .unwrap()
        .iter()
        .map(|k| (k["name"].as_str().unwrap(), k["kind"].as_str().unwrap()))
        .collect();
    assert_eq!(kinds, [("sink-a", "sink"), ("sink-b", "sink"), ("spring", "spring")]);
    let surfaces = data["surfaces"].as_array().unwrap();
    assert_eq!(surfaces.len(), 2, "the water table and the horizon");
    // The tiny horizon is the plane z = 45.
    assert!(surfaces[1]["z"].as_array().unwrap().iter().all(|z| z.as_f64() == Some(45.0)));
    let meshes = data["meshes"].as_array().unwrap();
    let names: Vec<&str> = meshes.iter().map(|m| m["name"].as_str().unwrap()).collect();
    assert_eq!(names, ["terrain", "cave", "water"]);
    for mesh in meshes {
        let mut triangles = 0;
        for chunk in mesh["chunks"].as_array().unwrap() {
            let levels = chunk["levels"].as_array().unwrap();
            triangles += levels[0]["triangles"].as_u64().unwrap();
            for level in levels {
                let bytes = std::fs::read(dir.join("view").join(level["file"].as_str().unwrap())).unwrap();
                assert_eq!(&bytes[..4], b"glTF");
                assert_eq!(bytes.len() as u64, level["bytes"].as_u64().unwrap());
            }
        }
        assert_eq!(triangles, mesh["triangles"].as_u64().unwrap(), "the finest levels hold every triangle");
    }
    let metrics: Value = serde_json::from_slice(&std::fs::read(dir.join("metrics.json")).unwrap()).unwrap();
    assert_eq!(data["metrics"]["network"]["n_nodes_full"], metrics["payload"]["network"]["n_nodes_full"]);
    assert!(metrics["payload"]["network"]["n_nodes_full"].as_u64().unwrap() > 2);
    assert!(dir.join("view/index.html").is_file());
    assert!(dir.join("view/vendor/three/LICENSE").is_file());
}

#[test]
fn the_view_does_not_depend_on_the_number_of_threads() {
    let write = |name: &str, threads: usize| {
        let dir = tiny_run(name, &[]);
        let pool = rayon::ThreadPoolBuilder::new().num_threads(threads).build().unwrap();
        pool.install(|| write_view(&dir, Some(&tiny_scene()))).unwrap();
        let mut out = BTreeMap::new();
        files(&dir.join("view"), "", &mut out);
        out
    };
    let (one, three) = (write("threads-1", 1), write("threads-3", 3));
    assert_eq!(one.keys().collect::<Vec<_>>(), three.keys().collect::<Vec<_>>());
    for (name, bytes) in &one {
        if name != "data/run.json" {
            assert!(bytes == &three[name], "{name} differs");
        }
    }
    // run.json names the run folder; everything else in it is the same.
    let strip = |b: &[u8]| {
        let mut v: Value = serde_json::from_slice(b).unwrap();
        v["run"] = Value::Null;
        v
    };
    assert_eq!(strip(&one["data/run.json"]), strip(&three["data/run.json"]));
}

#[test]
fn a_run_lacking_stages_is_shown_with_what_is_missing() {
    let dir = tiny_run("missing", &["mesh.bin", "hydro.json"]);
    let report = write_view(&dir, None).unwrap();
    let files: Vec<&str> = report.problems.iter().map(|p| p.file.as_str()).collect();
    assert_eq!(files, ["scene.path", "hydro.json", "mesh.bin"]);
    assert!(report.problems[2].message.contains("mesh.bin is missing"), "{:?}", report.problems[2]);
    let data = run_json(&dir);
    assert_eq!(data["problems"].as_array().unwrap().len(), 3);
    assert!(data["meshes"].as_array().unwrap().is_empty());
    assert!(data["hydro"].is_null());
    // Without the scene, the domain is the network's bounds and key points come from its nodes.
    assert!(data["domain"]["min"].is_array());
    assert_eq!(data["keypoints"].as_array().unwrap().len(), 3);
}

#[test]
fn streams_of_another_hydro_json_are_a_problem_and_still_shown() {
    let dir = tiny_run("stale-streams", &[]);
    let path = dir.join("streams.json");
    let text = std::fs::read_to_string(&path).unwrap();
    let artifact: Value = serde_json::from_str(&text).unwrap();
    let hydro = artifact["header"]["inputs"][0]["payload_blake3"].as_str().unwrap();
    std::fs::write(&path, text.replacen(hydro, &"0".repeat(64), 1)).unwrap();
    let report = write_view(&dir, Some(&tiny_scene())).unwrap();
    assert_eq!(report.problems.len(), 1, "{:?}", report.problems);
    assert!(report.problems[0].message.contains("--from streams"), "{}", report.problems[0].message);
    assert!(run_json(&dir)["streams"]["segments"].is_array());
}

#[test]
fn a_corrupted_artifact_is_a_problem_that_says_what_to_rerun() {
    let dir = tiny_run("corrupted", &[]);
    let path = dir.join("metrics.json");
    let mut bytes = std::fs::read(&path).unwrap();
    let last = bytes.len() - 10;
    bytes[last] ^= 0x01;
    std::fs::write(&path, bytes).unwrap();
    let report = write_view(&dir, Some(&tiny_scene())).unwrap();
    assert_eq!(report.problems.len(), 1);
    assert!(report.problems[0].message.contains("--from metrics"), "{}", report.problems[0].message);
    assert!(run_json(&dir)["metrics"].is_null());
}

#[test]
fn a_folder_that_is_not_a_run_is_refused() {
    let empty = scratch("empty");
    let err = write_view(&empty, None).unwrap_err();
    assert!(matches!(err, ViewError::NotARun { .. }), "{err}");
    assert!(err.to_string().contains("not a karstgen run"), "{err}");
    assert!(err.to_string().contains("karstgen run"), "{err}");
    assert_eq!(err.exit_code(), 2);
    assert!(!empty.join("view").exists());
    let err = write_view(&empty.join("nowhere"), None).unwrap_err();
    assert!(matches!(err, ViewError::NoFolder { .. }), "{err}");
}

#[test]
fn a_bad_scene_is_bad_input() {
    let dir = tiny_run("bad-scene", &[]);
    let scene = dir.join("broken.toml");
    std::fs::write(&scene, "name = \"x\"\n[domain]\nmin = [0, 0]\n").unwrap();
    let err = write_view(&dir, Some(&scene)).unwrap_err();
    assert!(err.to_string().contains("broken.toml"), "{err}");
    assert_eq!(err.exit_code(), 2);
}

#[test]
fn writing_again_replaces_the_view() {
    let dir = tiny_run("again", &[]);
    write_view(&dir, Some(&tiny_scene())).unwrap();
    std::fs::write(dir.join("view/data/stale.glb"), b"old").unwrap();
    write_view(&dir, Some(&tiny_scene())).unwrap();
    assert!(!dir.join("view/data/stale.glb").exists());
    let leftovers: Vec<_> = std::fs::read_dir(&dir)
        .unwrap()
        .flatten()
        .filter(|e| e.file_name().to_string_lossy().starts_with(".view"))
        .collect();
    assert!(leftovers.is_empty());
}

#[test]
fn an_ensemble_in_the_run_folder_colours_every_segment() {
    let dir = tiny_run("ensemble", &[]);
    let scene = SceneFile::load(&tiny_scene()).unwrap();
    let seed = scene.scene.seed();
    let plan = ensemble::Plan::new(scene, None, 10.0, ensemble::Keep::All).unwrap();
    ensemble::run(&plan, &dir, &[seed, seed + 1, seed + 2], None).unwrap();
    let report = write_view(&dir, Some(&tiny_scene())).unwrap();
    assert!(report.problems.is_empty(), "{:?}", report.problems);
    let data = run_json(&dir);
    assert_eq!(data["ensemble"]["realizations"], 3);
    let conduits = data["ensemble"]["segments"].as_array().unwrap();
    assert_eq!(conduits.len(), data["skeleton"]["conduits"].as_array().unwrap().len());
    for (c, segments) in conduits.iter().enumerate() {
        let expected = data["skeleton"]["conduits"][c]["nodes"].as_array().unwrap().len() - 1;
        assert_eq!(segments.as_array().unwrap().len(), expected);
        for p in segments.as_array().unwrap() {
            // The run is the realization of the scene's own seed: each of its segments counts once.
            let p = p.as_f64().unwrap();
            assert!((1.0 / 3.0 - 1e-6..=1.0 + 1e-6).contains(&p), "conduit {c}: probability {p}");
        }
    }
    std::fs::remove_file(dir.join("probability/z-000.exr")).unwrap();
    let report = write_view(&dir, Some(&tiny_scene())).unwrap();
    assert_eq!(report.problems.len(), 1);
    assert!(report.problems[0].message.contains("z-000.exr"), "{}", report.problems[0].message);
    assert!(run_json(&dir)["ensemble"].is_null());
}
