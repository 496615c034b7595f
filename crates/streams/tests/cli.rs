//! The command-line contract of `karst-streams`: bad controller curves and a hydro.json of
//! another scene exit with code 2 and a message naming the file, the entry and the value,
//! writing nothing; a climbing curve runs, lowered, with a note; `render` and `inspect` work.

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

use karst_artifact::{Provenance, write_artifact};
use karst_hydro::{FlowUnits, Hydro, NodeWater, Role, Spring};
use karst_testkit::{SceneText, scratch};

fn streams(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_karst-streams")).args(args).output().unwrap()
}

/// The tiny test scene with `extra` TOML, written into `dir` beside a hydro.json whose springs
/// are `springs` (all at its one node, a valid payload).
fn setup(dir: &Path, extra: &str, springs: &[&str]) -> PathBuf {
    let scene = dir.join("scene.toml");
    std::fs::write(&scene, SceneText::new("cli").with(extra).text()).unwrap();
    let hydro = Hydro {
        flow_units: FlowUnits { min: 1.0, max: 1.0 },
        conduits: Vec::new(),
        nodes: vec![NodeWater { role: Role::Well, inflow: 1.0 }],
        sinks: Vec::new(),
        springs: springs
            .iter()
            .map(|name| Spring { name: name.to_string(), node: 0, flow: 1.0, sinks: Vec::new() })
            .collect(),
    };
    let provenance = Provenance {
        producer: "test".into(),
        inputs: vec![],
        params: "test".into(),
        frame: Default::default(),
    };
    write_artifact(&dir.join("hydro.json"), &provenance, &hydro).unwrap();
    scene
}

fn run(scene: &Path, dir: &Path) -> Output {
    streams(&["run", scene.to_str().unwrap(), "--out", dir.to_str().unwrap()])
}

fn curve(kind: &str, points: &str) -> String {
    format!("[[streams.curves]]\nname = \"c\"\nkind = \"{kind}\"\nflow = 0.5\npoints = {points}\n")
}

#[test]
fn bad_controller_curves_exit_2_naming_the_entry_and_write_nothing() {
    // The curve's `points` line is line 30 of the scene text.
    let cases = [
        (
            curve("contact", "[[10, 50, 39], [40, nan, 37]]"),
            "scene.toml:30: streams.curves[0].points[1]: NaN is not a finite number",
        ),
        (
            curve("contact", "[[10, 50, 39], [400, 50, 37]]"),
            "streams.curves[0].points[1]: curve \"c\": [400, 50, 37] is outside the domain",
        ),
        (
            curve("contact", "[[10, 50, 39]]"),
            "streams.curves[0].points: curve \"c\" has a single point: a Contact curve needs at least 2",
        ),
        (
            curve("pool", "[]"),
            "streams.curves[0].points: curve \"c\" has no point: a Pool curve needs at least 3",
        ),
        (
            curve("free_fall", "[[10, 50, 39], [12, 50, 30], [14, 50, 20]]"),
            "free fall \"c\" has 3 points: give its lip and its foot only",
        ),
        (
            format!(
                "{}{}",
                curve("contact", "[[10, 50, 39], [40, 50, 37]]"),
                curve("contact", "[[20, 20, 39], [40, 20, 37]]")
            ),
            "streams.curves[1].name: \"c\" is used twice",
        ),
        (
            curve("contact", "[[10, 50, 39], [40, 50, 37]]").replace("flow = 0.5", "flow = -1"),
            "streams.curves[0].flow",
        ),
    ];
    for (extra, expected) in cases {
        let dir = scratch("bad-curve");
        let scene = setup(&dir, &extra, &["s"]);
        let result = run(&scene, &dir);
        let stderr = String::from_utf8_lossy(&result.stderr);
        assert_eq!(result.status.code(), Some(2), "{extra}: {stderr}");
        assert!(stderr.contains(expected), "{extra}: expected {expected:?} in {stderr}");
        assert!(stderr.contains("scene.toml"), "{stderr}");
        assert!(!dir.join("streams.json").exists(), "{extra}: nothing is written");
    }
}

#[test]
fn a_hydro_json_of_another_scene_exits_2_naming_it() {
    let dir = scratch("other-hydro");
    let scene = setup(&dir, "", &["elsewhere"]);
    let result = run(&scene, &dir);
    let stderr = String::from_utf8_lossy(&result.stderr);
    assert_eq!(result.status.code(), Some(2), "{stderr}");
    assert!(
        stderr.contains("hydro.json: names spring \"elsewhere\", which is not a spring of the scene")
            && stderr.contains("--from hydro"),
        "{stderr}"
    );
    assert!(!dir.join("streams.json").exists());
}

#[test]
fn a_climbing_curve_is_lowered_with_a_note_then_render_and_inspect() {
    let dir = scratch("climbing");
    let scene =
        setup(&dir, &curve("contact", "[[10, 50, 39], [40, 50, 37], [70, 50, 38.5], [95, 50, 30]]"), &["s"]);
    let result = run(&scene, &dir);
    let stderr = String::from_utf8_lossy(&result.stderr);
    assert!(result.status.success(), "{stderr}");
    assert!(stderr.contains("note: streams.curves[0] (\"c\"): points[2] lowered from 38.50 to"), "{stderr}");
    let png = dir.join("map.png");
    let d = dir.to_str().unwrap();
    let result = streams(&["render", scene.to_str().unwrap(), d, "--png", png.to_str().unwrap()]);
    assert!(result.status.success(), "{}", String::from_utf8_lossy(&result.stderr));
    assert_eq!(&std::fs::read(&png).unwrap()[1..4], b"PNG");
    let summary = streams(&["inspect", dir.join("streams.json").to_str().unwrap()]);
    let text = String::from_utf8_lossy(&summary.stdout);
    assert!(summary.status.success() && text.contains("streams, schema 1"), "{text}");
    assert!(text.contains("report    streams.curves[0] (\"c\"): points[2] lowered"), "{text}");
}
