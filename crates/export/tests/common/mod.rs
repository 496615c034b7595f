//! Helpers of the export tests: runs of the fixture scenes, the exports of a run, and the
//! outside tools (found through KARSTNET_PYTHON, KARSTGEN_NODE_MODULES and the PATH, all set
//! up by `cargo xtask test`; a missing tool fails the test, it never passes silently).
#![allow(dead_code)] // each test binary uses a different subset

use std::collections::HashMap;
use std::path::{Path, PathBuf};
use std::process::Command;
use std::sync::{Mutex, OnceLock};

use karst_artifact::{Payload, StageId, read_artifact};
use karst_export::{ExportFormat, ExportParams, Inputs, Manifest, export};
use karst_hydro::Hydro;
use karst_mesher::Mesh;
use karst_metrics::MetricsReport;
use karst_pipeline::make::{self, Selection};
use karst_pipeline::scene::SceneFile;
use karst_sampling::Samples;
use karst_scene::Scene;
use karst_skeleton::Skeleton;
use karst_streams::Streams;
pub use karst_testkit::{root, scratch};

/// The run of `fixtures/scenes/NAME.toml` (`NAME:LEVEL`: with `[sdf] passage_detail = LEVEL`)
/// up to streams and metrics (no mesh: the network
/// formats need none; the sdf only for the survey the metrics read), made once per test binary.
pub fn network_run(name: &str) -> PathBuf {
    static RUNS: OnceLock<Mutex<HashMap<String, PathBuf>>> = OnceLock::new();
    let runs = RUNS.get_or_init(Default::default);
    let mut runs = runs.lock().unwrap_or_else(|e| e.into_inner());
    runs.entry(name.to_string())
        .or_insert_with(|| {
            let (file, level) = name.split_once(':').map_or((name, None), |(f, l)| (f, Some(l)));
            let path = root().join(format!("fixtures/scenes/{file}.toml"));
            let scene = match level {
                None => SceneFile::load(&path).unwrap(),
                Some(level) => {
                    let text = std::fs::read_to_string(&path).unwrap();
                    assert!(!text.contains("\n[sdf]"), "{name}: the scene has its own [sdf]");
                    let text = format!("{text}\n[sdf]\npassage_detail = \"{level}\"\n");
                    SceneFile { scene: Scene::parse(&text, &path).unwrap(), path }
                }
            };
            let out = scratch(&format!("run-{name}")).keep();
            for stage in [
                StageId::Sampling,
                StageId::Costgraph,
                StageId::Skeleton,
                StageId::Hydro,
                StageId::Streams,
                StageId::Sdf,
                StageId::Survey,
                StageId::Metrics,
            ] {
                let only = Selection { only: Some(stage), ..Selection::default() };
                make::run(&scene, &out, &only, &mut |_| {})
                    .unwrap_or_else(|e| panic!("{name}: {}: {e}", stage.name()));
            }
            out
        })
        .clone()
}

/// The blessed run of the tiny scene: every artifact, mesh included.
pub fn tiny() -> PathBuf {
    root().join("fixtures/golden/tiny")
}

pub fn read<P: Payload>(dir: &Path, file: &str) -> P {
    read_artifact::<P>(&dir.join(file)).unwrap_or_else(|e| panic!("{e}")).1
}

/// The artifacts of a run; the mesh only when the run has one.
pub struct Run {
    pub skeleton: Skeleton,
    pub hydro: Hydro,
    pub streams: Streams,
    pub metrics: MetricsReport,
    pub samples: Samples,
    pub mesh: Option<Mesh>,
    /// The frame the artifacts record.
    pub frame: karst_artifact::Frame,
    /// The scene, for the formats that read it (the GIS formats).
    pub scene: Option<karst_scene::Scene>,
}

impl Run {
    pub fn load(dir: &Path) -> Run {
        let mesh_path = dir.join("mesh.bin");
        Run {
            skeleton: read(dir, "skeleton.json"),
            hydro: read(dir, "hydro.json"),
            streams: read(dir, "streams.json"),
            metrics: read(dir, "metrics.json"),
            samples: read(dir, "samples.bin"),
            mesh: mesh_path.exists().then(|| read(dir, "mesh.bin")),
            frame: karst_artifact::read_header(&dir.join("samples.bin")).unwrap().frame(),
            scene: None,
        }
    }

    /// The run with its scene, `fixtures/scenes/NAME.toml`.
    pub fn with_scene(mut self, name: &str) -> Run {
        let path = root().join(format!("fixtures/scenes/{name}.toml"));
        self.scene = Some(SceneFile::load(&path).unwrap().scene);
        self
    }

    pub fn inputs(&self) -> Inputs<'_> {
        Inputs {
            skeleton: Some(&self.skeleton),
            hydro: Some(&self.hydro),
            streams: Some(&self.streams),
            mesh: self.mesh.as_ref(),
            metrics: Some(&self.metrics),
            samples: Some(&self.samples),
            geology: None,
            keypoints: self.scene.as_ref().map(|s| &s.keypoints()[..]),
            terrain: self.scene.as_ref().map(|s| s.terrain()),
            domain: self.scene.as_ref().map(|s| s.domain()),
            frame: &self.frame,
        }
    }
}

/// Exports `formats` of `run` into a scratch folder; returns that folder (removed when dropped,
/// if the test passes), the export folder inside it and the manifest.
pub fn export_run(
    run: &Run,
    formats: &[ExportFormat],
    tag: &str,
) -> (karst_testkit::Scratch, PathBuf, Manifest) {
    export_with(run, &ExportParams { formats: formats.to_vec(), ..ExportParams::default() }, tag)
}

/// Exports `run` with `params` into a scratch folder, as [`export_run`].
pub fn export_with(
    run: &Run,
    params: &ExportParams,
    tag: &str,
) -> (karst_testkit::Scratch, PathBuf, Manifest) {
    let dir = scratch(tag);
    let manifest = export(&run.inputs(), params, &dir).unwrap_or_else(|e| panic!("{tag}: {e}"));
    let folder = dir.join(karst_export::FOLDER);
    (dir, folder, manifest)
}

/// The venv's Python with karstnet, vtk and swmm-toolkit.
pub fn python() -> String {
    std::env::var("KARSTNET_PYTHON").unwrap_or_else(|_| {
        panic!("set KARSTNET_PYTHON (run the tests with `cargo xtask test`, which installs the tools)")
    })
}

/// Runs a helper script of tests/tools with the venv's Python and parses its JSON output.
pub fn python_json(script: &str, args: &[&str]) -> serde_json::Value {
    let script = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/tools").join(script);
    let name = script_name(&script).to_string();
    run_json(Command::new(python()).arg(&script).args(args), &name)
}

/// The Khronos glTF-Validator's report of a file.
pub fn validate_gltf(file: &Path) -> serde_json::Value {
    let modules = std::env::var("KARSTGEN_NODE_MODULES").unwrap_or_else(|_| {
        panic!(
            "set KARSTGEN_NODE_MODULES (run the tests with `cargo xtask test`, which installs gltf-validator)"
        )
    });
    let script = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/tools/validate_gltf.mjs");
    run_json(Command::new("node").arg(script).arg(modules).arg(file), "gltf-validator")
}

fn script_name(path: &Path) -> &str {
    path.file_name().and_then(|n| n.to_str()).unwrap_or("script")
}

fn run_json(command: &mut Command, what: &str) -> serde_json::Value {
    let out = command
        .output()
        .unwrap_or_else(|e| panic!("cannot run {what} (run `cargo xtask test` to install the tools): {e}"));
    assert!(out.status.success(), "{what} failed:\n{}", String::from_utf8_lossy(&out.stderr));
    let stdout = String::from_utf8_lossy(&out.stdout);
    let last = stdout
        .lines()
        .rev()
        .find(|l| l.starts_with('{'))
        .unwrap_or_else(|| panic!("{what} printed no JSON:\n{stdout}"));
    serde_json::from_str(last).unwrap_or_else(|e| panic!("{what}: {e}"))
}

/// Runs a program of the PATH in `dir`; panics (saying how to install it) when it is missing.
pub fn run_tool(program: &str, args: &[&str], dir: &Path) -> std::process::Output {
    Command::new(program)
        .args(args)
        .current_dir(dir)
        .output()
        .unwrap_or_else(|e| panic!("cannot run {program} (run `cargo xtask test`, which installs it): {e}"))
}
