//! The viewer in a real browser: the default scene is run in process, its view written and
//! served on loopback, and `browser.mjs` drives Debian's headless Chromium through it with
//! puppeteer-core (see that script for the assertions). The tools come from
//! `cargo xtask test` (tools/apt-packages.txt, tools/node): without them the test fails.

use std::path::{Path, PathBuf};
use std::process::Command;

use karst_pipeline::make::{self, Selection};
use karst_pipeline::scene::SceneFile;
use karst_testkit::{root, scratch};
use karst_view::{Server, write_view};

const CHROMIUM: &str = "/usr/bin/chromium";

/// tools/node/node_modules, checked; panics with what to do when the tools are missing.
fn node_modules() -> PathBuf {
    let Some(modules) = std::env::var_os("KARSTGEN_NODE_MODULES").map(PathBuf::from) else {
        panic!(
            "KARSTGEN_NODE_MODULES is not set: run the tests with `cargo xtask test`, which installs the browser tools"
        );
    };
    assert!(
        modules.join("puppeteer-core/package.json").is_file(),
        "{} has no puppeteer-core: run `cargo xtask test` (npm ci in tools/node)",
        modules.display()
    );
    assert!(
        Path::new(CHROMIUM).is_file(),
        "{CHROMIUM} is missing: run `cargo xtask test` (installs tools/apt-packages.txt) or `apt-get install chromium`"
    );
    modules
}

/// Runs `browser.mjs MODE URL ARG` and returns its JSON line; panics with its output on failure.
fn drive(modules: &Path, mode: &str, url: &str, arg: &Path) -> String {
    let script = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/browser.mjs");
    let output = Command::new("node")
        .arg(&script)
        .args([mode, url])
        .arg(arg)
        .env("KARSTGEN_NODE_MODULES", modules)
        .output()
        .expect("node runs (run `cargo xtask test` to install the tools)");
    let stdout = String::from_utf8_lossy(&output.stdout).into_owned();
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert!(output.status.success(), "browser.mjs {mode} failed:\n{stdout}\n{stderr}");
    stdout
}

fn serve(view: &Path) -> String {
    let server = Server::bind(view, 0).expect("a free port on 127.0.0.1");
    let url = server.url();
    std::thread::spawn(move || server.run());
    url
}

#[test]
fn the_default_scene_in_headless_chromium() {
    let modules = node_modules();
    let out = scratch("view-browser");
    let scene = root().join("fixtures/scenes/default.toml");
    make::run(
        &SceneFile::load(&scene).expect("the default scene loads"),
        &out,
        &Selection::default(),
        &mut |_| {},
    )
    .expect("the default scene runs");
    let report = write_view(&out, Some(&scene)).unwrap();
    assert!(report.problems.is_empty(), "{:?}", report.problems);
    let results = drive(&modules, "test", &serve(&report.dir), &out);
    println!("default scene: {results}");

    // The same run without its meshes: the page lists what is missing, with no error.
    let partial = out.join("partial");
    std::fs::create_dir_all(&partial).unwrap();
    for file in ["skeleton.json", "hydro.json", "metrics.json"] {
        std::fs::copy(out.join(file), partial.join(file)).unwrap();
    }
    let report = write_view(&partial, Some(&scene)).unwrap();
    let results = drive(&modules, "missing", &serve(&report.dir), Path::new("mesh.bin"));
    println!("without meshes: {results}");
}
