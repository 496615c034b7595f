//! `karst-export DIR`: what it writes, and bad input (exit code 2, a message naming what is
//! wrong, the run's artifacts untouched).

mod common;

use std::path::Path;
use std::process::{Command, Output};

use common::{scratch, tiny};

fn karst_export(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_karst-export")).args(args).output().expect("run karst-export")
}

fn stderr(out: &Output) -> String {
    String::from_utf8_lossy(&out.stderr).into_owned()
}

/// A copy of the tiny run's artifacts in a scratch folder.
fn copy_of_tiny(tag: &str, files: &[&str]) -> karst_testkit::Scratch {
    let dir = scratch(tag);
    for f in files {
        std::fs::copy(tiny().join(f), dir.join(f)).unwrap();
    }
    dir
}

/// The files of `dir` and their hashes, but the empty lock file every writer of a run folder
/// holds while it writes (karst_artifact::lock; it stays, as lock files do).
fn digest(dir: &Path) -> Vec<(String, String)> {
    let mut files: Vec<(String, String)> = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap())
        .filter(|e| e.path().is_file() && e.file_name() != karst_artifact::lock::LOCK_FILE)
        .map(|e| {
            (
                e.file_name().to_string_lossy().into_owned(),
                blake3::hash(&std::fs::read(e.path()).unwrap()).to_hex().to_string(),
            )
        })
        .collect();
    files.sort();
    files
}

const ALL: [&str; 6] =
    ["skeleton.json", "hydro.json", "streams.json", "metrics.json", "samples.bin", "mesh.bin"];

#[test]
fn default_formats_of_the_tiny_run() {
    let dir = copy_of_tiny("cli-default", &ALL);
    let scene = common::root().join("fixtures/scenes/tiny.toml");
    let out = karst_export(&[dir.to_str().unwrap(), "--scene", scene.to_str().unwrap(), "--json"]);
    assert!(out.status.success(), "{}", stderr(&out));
    let manifest: karst_export::Manifest = serde_json::from_slice(&out.stdout).unwrap();
    let formats: std::collections::BTreeSet<&str> =
        manifest.files.iter().map(|f| f.format.as_str()).collect();
    assert_eq!(formats, ["csv", "gltf", "gocad", "survex", "swmm", "vtk"].into_iter().collect());
    for f in &manifest.files {
        assert!(dir.join("export").join(&f.name).is_file(), "{}", f.name);
    }
}

#[test]
fn unknown_format_is_refused_before_anything_is_read() {
    let dir = scratch("cli-unknown");
    let out = karst_export(&[dir.to_str().unwrap(), "--format", "vtk,shapefile"]);
    assert_eq!(out.status.code(), Some(2));
    assert!(stderr(&out).contains("unknown format `shapefile`"), "{}", stderr(&out));
    assert!(!dir.join("export").exists());
}

#[test]
fn a_format_whose_input_the_run_lacks_is_refused() {
    let dir = copy_of_tiny("cli-missing", &["skeleton.json", "hydro.json"]);
    let before = digest(&dir);
    let out = karst_export(&[dir.to_str().unwrap(), "--format", "survex,gltf"]);
    assert_eq!(out.status.code(), Some(2));
    assert!(stderr(&out).contains("`gltf` needs mesh.bin"), "{}", stderr(&out));
    assert!(!dir.join("export").exists(), "nothing written");
    assert_eq!(digest(&dir), before);
    let out = karst_export(&[dir.to_str().unwrap(), "--format", "vtk"]);
    assert_eq!(out.status.code(), Some(2));
    assert!(stderr(&out).contains("`vtk` needs streams.json"), "{}", stderr(&out));
    assert!(!dir.join("export").exists(), "nothing written");
}

#[test]
fn unwritable_export_folder_and_corrupt_artifact_exit_2_and_touch_nothing() {
    let dir = copy_of_tiny("cli-unwritable", &["skeleton.json", "hydro.json"]);
    std::fs::write(dir.join("export"), b"a file where the folder goes").unwrap();
    let before = digest(&dir);
    let out = karst_export(&[dir.to_str().unwrap(), "--format", "survex"]);
    assert_eq!(out.status.code(), Some(2));
    assert!(stderr(&out).contains("cannot write"), "{}", stderr(&out));
    assert_eq!(digest(&dir), before);

    std::fs::remove_file(dir.join("export")).unwrap();
    let mut hydro = std::fs::read(dir.join("hydro.json")).unwrap();
    let last = hydro.len() - 10;
    hydro[last] ^= 0x20;
    std::fs::write(dir.join("hydro.json"), hydro).unwrap();
    let out = karst_export(&[dir.to_str().unwrap(), "--format", "survex"]);
    assert_eq!(out.status.code(), Some(2));
    assert!(stderr(&out).contains("hydro.json"), "{}", stderr(&out));
}

#[test]
fn bad_export_section_names_the_field_and_value() {
    let dir = scratch("cli-scene");
    let scene = dir.join("s.toml");
    let tiny_scene = std::fs::read_to_string(common::root().join("fixtures/scenes/tiny.toml")).unwrap();
    std::fs::write(&scene, format!("{tiny_scene}\n[export]\nformats = [\"vtk\", \"dxf\"]\n")).unwrap();
    let out = karst_export(&[dir.to_str().unwrap(), "--scene", scene.to_str().unwrap()]);
    assert_eq!(out.status.code(), Some(2));
    let err = stderr(&out);
    assert!(err.contains("export.formats") && err.contains("dxf"), "{err}");
}
