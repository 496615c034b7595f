//! `karstgen calibrate`: reproducible whatever the number of threads, and every bad input (the
//! target cave, the parameter box) refused with exit code 2 and a message naming it.

use std::path::{Path, PathBuf};

use karst_pipeline::calibrate::optimiser::{Optimiser, Start};
use karst_pipeline::calibrate::{Aim, CalibrateArgs, run, run_with};
use karst_stage::StageError;
use karst_testkit::{fixture, scratch};

/// The tiny scene with a calibration box of three parameters and a budget of two generations of
/// three candidates on two seeds.
const BOX: &str = r#"
[calibrate]
seeds = 2
evaluations = 7
population = 3

[[calibrate.parameters]]
name = "skeleton.amplification_points"
min = 0
max = 8

[[calibrate.parameters]]
name = "skeleton.amplification_steps"
min = 0
max = 2

[[calibrate.parameters]]
name = "skeleton.tortuosity"
min = 0.0
max = 1.0
"#;

fn tiny_with(dir: &Path, calibrate: &str) -> PathBuf {
    let text = std::fs::read_to_string(fixture("fixtures/scenes/tiny.toml")).unwrap();
    let path = dir.join("scene.toml");
    std::fs::write(&path, format!("{text}\n{calibrate}")).unwrap();
    path
}

fn calibrate(scene: &Path, target: &[PathBuf], out: &Path) -> Result<String, StageError> {
    run(&CalibrateArgs {
        scene: scene.to_path_buf(),
        target: Some(Aim::Cave(target.to_vec())),
        out: out.to_path_buf(),
    })
}

fn outputs(out: &Path) -> Vec<(String, Vec<u8>)> {
    ["calibrated.toml", "report.json", "report.png", "iterations.csv"]
        .iter()
        .map(|f| (f.to_string(), std::fs::read(out.join(f)).unwrap()))
        .collect()
}

#[test]
fn same_scene_same_report_with_one_or_two_threads() {
    let dir = scratch("calibrate-threads");
    let scene = tiny_with(&dir, BOX);
    let target = [fixture("fixtures/caves/Monachou.pl")];
    let with_threads = |threads: usize| {
        let out = dir.join(format!("out-{threads}"));
        let pool = rayon::ThreadPoolBuilder::new().num_threads(threads).build().unwrap();
        pool.install(|| calibrate(&scene, &target, &out)).unwrap();
        outputs(&out)
    };
    let (one, two) = (with_threads(1), with_threads(2));
    for ((name, a), (_, b)) in one.iter().zip(&two) {
        assert!(a == b, "{name} differs between 1 and 2 threads");
    }
    let report: serde_json::Value = serde_json::from_slice(&one[1].1).unwrap();
    assert_eq!(report["candidates"], 7, "the scene and two generations of three");
    assert_eq!(report["generations"], 2);
    let (before, after) =
        (report["distance"]["before"].as_f64().unwrap(), report["distance"]["after"].as_f64().unwrap());
    assert!(after <= before && after > 0.0, "{before} → {after}");
    let (width, height, colours) = karst_plot::testing::png_summary(&one[2].1);
    assert!(width == 900 && height > 400 && colours > 10, "report.png {width}×{height}, {colours} colours");
    let log = String::from_utf8(one[3].1.clone()).unwrap();
    assert_eq!(log.lines().count(), 8, "a header and one row per candidate");
    // The calibrated scene runs: it parses, and carries the best candidate's values (none when
    // the best is the scene itself with its derived default, which stays unset).
    let calibrated = String::from_utf8(one[0].1.clone()).unwrap();
    let parsed = karst_scene::Scene::parse(&calibrated, &dir.join("calibrated.toml")).unwrap();
    assert_eq!(parsed.name(), "tiny-calibrated");
    let best = report["parameters"][0]["after"].as_f64();
    assert_eq!(parsed.skeleton().amplification_points.map(|p| p as f64), best);
    std::fs::remove_dir_all(&dir).unwrap();
}

/// The tiny scene's network parameters against the real Sakany cave: two seeds, the scene and
/// three generations of four candidates, the box of the default scene's amplification,
/// tortuosity and dead ends.
const SAKANY_BOX: &str = r#"
[calibrate]
seeds = 2
evaluations = 13
population = 4

[[calibrate.parameters]]
name = "skeleton.amplification_steps"
min = 0
max = 4

[[calibrate.parameters]]
name = "skeleton.amplification_points"
min = 0
max = 24

[[calibrate.parameters]]
name = "skeleton.dead_end_fraction"
min = 0.0
max = 1.0

[[calibrate.parameters]]
name = "skeleton.tortuosity"
min = 0.0
max = 1.0
"#;

/// The least relative reduction of the distance to Sakany the search must reach: about half of
/// what CMA-ES reaches with this budget (36.5 %; the run is deterministic), far above what the
/// scene alone gives (0). The network defaults of issue 38 (loops, fewer tributaries) start tiny
/// closer to Sakany: before them the search reached 84 % from farther away.
const LEAST_REDUCTION: f64 = 0.18;

/// Calibrates the tiny scene to Sakany with `calibrate` ([`run`] or [`run_with`] another
/// optimiser); returns the relative reduction of the distance (1 − after / before) from
/// `report.json`.
fn sakany_reduction(name: &str, calibrate: impl FnOnce(&CalibrateArgs) -> Result<String, StageError>) -> f64 {
    let dir = scratch(name);
    let scene = tiny_with(&dir, SAKANY_BOX);
    let target = [fixture("fixtures/caves/Sakany_nodes.dat")];
    let out = dir.join("out");
    let args = CalibrateArgs { scene, target: Some(Aim::Cave(target.to_vec())), out: out.clone() };
    calibrate(&args).unwrap();
    let report: serde_json::Value =
        serde_json::from_slice(&std::fs::read(out.join("report.json")).unwrap()).unwrap();
    assert_eq!(report["candidates"], 13, "the scene and three generations of four");
    std::fs::remove_dir_all(&dir).unwrap();
    report["distance"]["reduction"].as_f64().unwrap()
}

/// The gain is required, not just allowed: `after <= before` holds for any optimiser since the
/// scene itself is a candidate.
fn assert_calibrates(reduction: f64) {
    assert!(
        reduction >= LEAST_REDUCTION,
        "distance to Sakany reduced by {:.1} %, less than {:.0} %",
        100.0 * reduction,
        100.0 * LEAST_REDUCTION
    );
}

#[test]
fn cma_es_brings_the_tiny_scene_closer_to_sakany() {
    let reduction = sakany_reduction("calibrate-sakany", run);
    assert_calibrates(reduction);
}

/// An optimiser that proposes the scene's own values, generation after generation.
struct Identity {
    start: Start,
}

impl Optimiser for Identity {
    fn lambda(&self) -> usize {
        self.start.population.unwrap_or(4)
    }
    fn sigma(&self) -> f64 {
        self.start.sigma
    }
    fn ask(&mut self) -> Vec<Vec<f64>> {
        vec![self.start.mean.clone(); self.lambda()]
    }
    fn tell(&mut self, _: &[f64]) {}
}

#[test]
#[should_panic(expected = "distance to Sakany reduced by")]
fn the_sakany_check_fails_without_a_search() {
    assert_calibrates(sakany_reduction("calibrate-identity", |args| {
        run_with(args, |start| Identity { start })
    }));
}

/// Runs a calibration expected to fail with exit code 2; returns its message.
fn refused(scene: &Path, target: &[PathBuf], out: &Path) -> String {
    let e = calibrate(scene, target, out).expect_err("bad input");
    assert_eq!(e.exit_code(), 2, "{e}");
    e.to_string()
}

#[test]
fn bad_targets_exit_2_naming_the_file() {
    let dir = scratch("calibrate-targets");
    let scene = tiny_with(&dir, BOX);
    let out = dir.join("out");
    let missing = dir.join("nowhere_nodes.dat");
    assert!(refused(&scene, &[missing], &out).contains("nowhere_nodes.dat"));
    let broken = dir.join("broken.pl");
    std::fs::write(&broken, "GOCAD PLine 1\nVRTX 1 0 0 zero\nSEG 1 2\n").unwrap();
    let message = refused(&scene, std::slice::from_ref(&broken), &out);
    assert!(message.contains("broken.pl:2") && message.contains("zero"), "{message}");
    let empty = dir.join("empty.pl");
    std::fs::write(&empty, "GOCAD PLine 1\nVRTX 1 0 0 0\n").unwrap();
    assert!(refused(&scene, &[empty], &out).contains("empty.pl"));
    let one_csv = dir.join("nodes.csv");
    std::fs::write(&one_csv, "id,x,y\n1,0,0\n").unwrap();
    assert!(refused(&scene, &[one_csv], &out).contains("two files"));
    let other = dir.join("cave.shp");
    std::fs::write(&other, "").unwrap();
    assert!(refused(&scene, &[other], &out).contains("unknown network format"));
    assert!(!out.exists(), "nothing written for a bad target");
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn bad_boxes_exit_2_naming_the_field_and_value() {
    let dir = scratch("calibrate-boxes");
    let target = [fixture("fixtures/caves/Sakany_nodes.dat")];
    let out = dir.join("out");
    let parameter = |name: &str, min: &str, max: &str| {
        format!("[calibrate]\n\n[[calibrate.parameters]]\nname = \"{name}\"\nmin = {min}\nmax = {max}\n")
    };
    let cases = [
        (parameter("skeleton.nonsense", "0", "1"), "calibrate.parameters[0].name", "\"skeleton.nonsense\""),
        (parameter("skeleton.tortuosity", "0.8", "0.2"), "calibrate.parameters[0].max", "[0.8, 0.2]"),
        (parameter("skeleton.cohesion_vadose", "0.5", "1.5"), "calibrate.parameters[0].max", "1.5"),
        (parameter("skeleton.amplification_steps", "0", "2.5"), "calibrate.parameters[0].max", "2.5"),
        (parameter("skeleton.gamma", "1", "3"), "calibrate.parameters[0].name", "skeleton.mode"),
        (parameter("costgraph.w_horizon", "0", "3"), "calibrate.parameters[0].name", "costgraph.model"),
        ("[calibrate]\nseeds = 0\n".to_string(), "calibrate.seeds", "got 0"),
        ("[calibrate]\n".to_string(), "calibrate.parameters", "empty"),
    ];
    for (section, field, value) in cases {
        let scene = tiny_with(&dir, &section);
        let message = refused(&scene, &target, &out);
        assert!(message.contains(field) && message.contains(value), "{section}\n→ {message}");
        assert!(message.contains("scene.toml:"), "names the file and line: {message}");
    }
    let without = tiny_with(&dir, "");
    assert!(refused(&without, &target, &out).contains("no [calibrate] section"));
    assert!(!out.exists(), "nothing written for a bad box");
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn like_aims_at_a_published_network_by_name() {
    let dir = scratch("calibrate-like");
    let scene = tiny_with(&dir, BOX);
    let like = |name: &str, out: &Path| {
        run(&CalibrateArgs {
            scene: scene.clone(),
            target: Some(Aim::Like(name.to_string())),
            out: out.to_path_buf(),
        })
    };
    let unknown = dir.join("out-unknown");
    let e = like("Lascaux", &unknown).expect_err("no such network");
    assert_eq!(e.exit_code(), 2, "{e}");
    assert!(e.to_string().contains("--like Lascaux") && e.to_string().contains("Sakany"), "{e}");
    assert!(!unknown.exists(), "nothing written for an unknown name");
    let out = dir.join("out-surveyed");
    let summary = like("SURVEYED", &out).unwrap();
    assert!(summary.contains("median of 25 surveyed caves"), "{summary}");
    let report: serde_json::Value =
        serde_json::from_slice(&std::fs::read(out.join("report.json")).unwrap()).unwrap();
    assert_eq!(report["target"], "median of 25 surveyed caves");
    let (before, after) =
        (report["distance"]["before"].as_f64().unwrap(), report["distance"]["after"].as_f64().unwrap());
    assert!(after <= before && after > 0.0, "{before} → {after}");
    // The summary ends with the calibrated scene's verdict against the target, and the
    // calibrated scene records its target, so that its runs report against it.
    let verdict = summary.lines().nth(1).unwrap_or_default();
    assert!(verdict.starts_with("verdict of the calibrated scene: "), "{summary}");
    assert!(verdict.contains("on target (median of 25 surveyed caves)"), "{summary}");
    let calibrated = std::fs::read_to_string(out.join("calibrated.toml")).unwrap();
    assert!(calibrated.contains("like = \"SURVEYED\""), "{calibrated}");
    // Without --like or --target, the scene's own target.
    let own = tiny_with(&dir, &BOX.replace("[calibrate]\n", "[calibrate]\nlike = \"Sakany\"\n"));
    let summary = run(&CalibrateArgs { scene: own, target: None, out: dir.join("out-own") }).unwrap();
    assert!(summary.contains(" to Sakany: ") && summary.contains("on target (Sakany)"), "{summary}");
    let none = tiny_with(&dir, BOX);
    let e = run(&CalibrateArgs { scene: none, target: None, out: dir.join("out-none") }).unwrap_err();
    assert_eq!(e.exit_code(), 2, "{e}");
    assert!(e.to_string().contains("no calibration target"), "{e}");
    std::fs::remove_dir_all(&dir).unwrap();
}
