//! The tiny scene's artifacts are pinned in fixtures/golden/tiny: a change in any stage's output
//! shows here (rerun `cargo xtask bless` and explain the change in the commit).

use karst_pipeline::diff;
use karstgen_tests::{artifacts, root, run_with_threads, scratch};

#[test]
fn tiny_scene_matches_the_golden_artifacts() {
    let out = scratch("golden");
    run_with_threads(&root().join("fixtures/scenes/tiny.toml"), &out, 2).unwrap();
    let golden = root().join("fixtures/golden/tiny");
    let mut failures = Vec::new();
    for (stage, path) in artifacts(&out) {
        let report = diff::diff(&golden.join(stage.file_name()), &path, 1e-9).unwrap();
        if report.differs() {
            failures.push(format!("{}:\n{}", stage.file_name(), report.summary()));
        }
    }
    assert!(failures.is_empty(), "artifacts differ from the goldens:\n{}", failures.join("\n"));
}

#[test]
fn one_or_two_threads_give_byte_identical_artifacts() {
    let scene = root().join("fixtures/scenes/tiny.toml");
    let (one, two) = (scratch("threads-1"), scratch("threads-2"));
    run_with_threads(&scene, &one, 1).unwrap();
    run_with_threads(&scene, &two, 2).unwrap();
    for ((stage, a), (_, b)) in artifacts(&one).into_iter().zip(artifacts(&two)) {
        assert!(std::fs::read(a).unwrap() == std::fs::read(b).unwrap(), "{} differs", stage.file_name());
    }
}
