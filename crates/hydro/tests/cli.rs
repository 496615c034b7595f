//! The command-line contract of `karst-hydro`: a bad [hydro] section and a bad skeleton exit
//! with code 2 and a message naming the file and the culprit; `render` writes a PNG.

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

use karst_artifact::{Provenance, read_artifact, write_artifact};
use karst_skeleton::Skeleton;
use karst_testkit::{root, scratch};

fn hydro(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_karst-hydro")).args(args).output().unwrap()
}

/// Runs the tiny scene up to the skeleton in `out`.
fn tiny_skeleton(out: &Path) -> PathBuf {
    let scene = root().join("fixtures/scenes/tiny.toml");
    let args = (scene.clone(), out.to_path_buf());
    karst_testkit::run::<karst_sampling::SamplingStage>(&args.0, &args.1).unwrap();
    karst_testkit::run::<karst_costgraph::CostgraphStage>(&args.0, &args.1).unwrap();
    karst_testkit::run::<karst_skeleton::SkeletonStage>(&args.0, &args.1).unwrap();
    scene
}

#[test]
fn bad_hydro_section_exits_2_naming_line_and_field() {
    let out = scratch("bad-scene");
    let scene = root().join("fixtures/bad/hydro_flow_radius.toml");
    let result = hydro(&["run", scene.to_str().unwrap(), "--out", out.to_str().unwrap()]);
    let stderr = String::from_utf8_lossy(&result.stderr);
    assert_eq!(result.status.code(), Some(2), "{stderr}");
    assert!(
        stderr.contains("hydro_flow_radius.toml:57: hydro.flow_radius: [3, 1] is not a range"),
        "{stderr}"
    );
}

#[test]
fn bad_skeletons_exit_2_naming_the_file_and_the_sink() {
    let out = scratch("bad-skeleton");
    let scene = tiny_skeleton(&out);
    let path = out.join("skeleton.json");
    let (_, good) = read_artifact::<Skeleton>(&path).unwrap();
    let provenance = Provenance {
        producer: "test".into(),
        inputs: vec![],
        params: "test".into(),
        frame: Default::default(),
    };
    let run = |skeleton: &Skeleton| {
        write_artifact(&path, &provenance, skeleton).unwrap();
        let result = hydro(&["run", scene.to_str().unwrap(), "--out", out.to_str().unwrap()]);
        assert_eq!(result.status.code(), Some(2));
        String::from_utf8_lossy(&result.stderr).into_owned()
    };
    let mut negative = good.clone();
    negative.routes[1].weight = -3.0;
    let sink = negative.routes[1].sink.clone();
    let e = run(&negative);
    assert!(e.contains("skeleton.json: routes[1].weight: -3 is not a finite number in [0, "), "{e}");
    assert!(e.contains("rerun the pipeline from skeleton"), "{sink}: {e}");

    let mut no_spring = good.clone();
    no_spring.routes.clear();
    no_spring.nodes.iter_mut().for_each(|n| n.keypoint = None);
    assert!(run(&no_spring).contains("the network has no spring"));

    // Cut every conduit at the spring: the sinks are left with no way down.
    let mut cut = good.clone();
    let spring = *good.routes[0].nodes.last().unwrap();
    cut.conduits.retain(|c| !c.nodes.contains(&spring));
    let e = run(&cut);
    assert!(e.contains("sink \"sink-") && e.contains("has no downstream path"), "{e}");
}

#[test]
fn run_render_and_inspect() {
    let out = scratch("ok");
    let scene = tiny_skeleton(&out);
    let dir = out.to_str().unwrap();
    assert!(hydro(&["run", scene.to_str().unwrap(), "--out", dir]).status.success());
    let png = out.join("water.png");
    let result = hydro(&["render", dir, "--png", png.to_str().unwrap()]);
    assert!(result.status.success(), "{}", String::from_utf8_lossy(&result.stderr));
    assert_eq!(&std::fs::read(&png).unwrap()[1..4], b"PNG");
    let summary = hydro(&["inspect", out.join("hydro.json").to_str().unwrap()]);
    assert!(String::from_utf8_lossy(&summary.stdout).contains("spring    spring: 4"));
}

#[test]
fn pool_weights_naming_no_pool_exit_2_naming_the_scene_and_the_entry() {
    let out = scratch("pool");
    let tiny = tiny_skeleton(&out);
    // The same scene with weights for a pool 1 km outside the network.
    let scene = out.join("tiny-pools.toml");
    let text = std::fs::read_to_string(&tiny).unwrap()
        + "\n[[hydro.pools]]\nat = [5000.0, 5000.0, 0.0]\noutlets = [{ towards = [0.0, 0.0, 0.0], weight = 1.0 }]\n";
    std::fs::write(&scene, text).unwrap();
    let result = hydro(&["run", scene.to_str().unwrap(), "--out", out.to_str().unwrap()]);
    let stderr = String::from_utf8_lossy(&result.stderr);
    assert_eq!(result.status.code(), Some(2), "{stderr}");
    assert!(
        stderr.contains("tiny-pools.toml: hydro.pools[0]: no pool within 10 m of [5000.0, 5000.0, 0.0] ("),
        "{stderr}"
    );
}

#[test]
fn a_catchment_grid_beyond_the_memory_budget_is_refused_before_allocating() {
    let out = scratch("catchment");
    let tiny = tiny_skeleton(&out);
    let scene = out.join("tiny-catchment.toml");
    let text = std::fs::read_to_string(&tiny).unwrap()
        + "\n[hydro]\nrecharge = \"catchment\"\ncatchment_cell = 1e-4\n";
    std::fs::write(&scene, text).unwrap();
    let result = hydro(&["run", scene.to_str().unwrap(), "--out", out.to_str().unwrap()]);
    let stderr = String::from_utf8_lossy(&result.stderr);
    assert_eq!(result.status.code(), Some(2), "{stderr}");
    assert!(
        stderr.contains(
            "tiny-catchment.toml: hydro.catchment_cell = 1.00e-4 means about 3.00e12 catchment cells"
        ),
        "{stderr}"
    );
    assert!(stderr.contains("hydro.catchment_cell = 0.0075 would fit"), "{stderr}");
    // A smaller budget refuses a cell the default one takes.
    let small =
        hydro(&["run", scene.to_str().unwrap(), "--out", out.to_str().unwrap(), "--max-memory", "1M"]);
    assert_eq!(small.status.code(), Some(2));
}
