//! The verdict that closes a run: the count of metrics inside the real-cave ranges and a hint per
//! metric outside, also when the metrics were up to date, and nothing when the run stopped
//! before them.

use karst_artifact::StageId;
use karst_pipeline::make::{self, Outcome, Selection};
use karst_pipeline::scene::SceneFile;
use karst_pipeline::verdict::verdict;
use karst_testkit::{fixture, scratch};

/// tiny with branch lengths all alike (no tributaries, no meanders): the cv of the branch
/// lengths falls below the real caves'.
const EVEN: &str = "[skeleton]\namplification_steps = 0\namplification_points = 0\ntortuosity = 0.0\n";

#[test]
fn a_run_ends_with_the_count_inside_and_a_hint_per_metric_outside() {
    let dir = scratch("verdict");
    let text = std::fs::read_to_string(fixture("fixtures/scenes/tiny.toml")).unwrap();
    let path = dir.join("scene.toml");
    assert!(text.contains("[skeleton]\n"), "tiny has a [skeleton] section");
    std::fs::write(&path, text.replacen("[skeleton]\n", EVEN, 1)).unwrap();
    let scene = SceneFile::load(&path).unwrap();
    let out = dir.join("out");
    let to = |stage| Selection { to: Some(stage), ..Selection::default() };
    let reports = make::run(&scene, &out, &to(StageId::Skeleton), &mut |_| {}).unwrap();
    assert!(verdict(&out, &reports).unwrap().is_empty(), "no verdict before the metrics ran");

    let reports = make::run(&scene, &out, &to(StageId::Metrics), &mut |_| {}).unwrap();
    let lines = verdict(&out, &reports).unwrap();
    let (inside, total) = lines[0]
        .strip_prefix("verdict: ")
        .and_then(|v| v.strip_suffix(" inside real-cave ranges"))
        .and_then(|v| v.split_once('/'))
        .unwrap_or_else(|| panic!("{lines:?}"));
    let (inside, total): (usize, usize) = (inside.parse().unwrap(), total.parse().unwrap());
    assert_eq!(total, 10);
    assert!(inside < 10, "{lines:?}");
    assert_eq!(lines.len() - 1, 10 - inside, "one hint per metric outside: {lines:?}");
    assert!(lines[1..].iter().all(|h| h.starts_with("  hint: ") && h.contains(" is ")), "{lines:?}");
    assert!(
        lines.iter().any(|h| h.contains("skeleton.amplification_steps is 0")
            || h.contains("skeleton.amplification_points is 0")
            || h.contains("skeleton.amplification_exponent is")),
        "the hints cite the tributaries this scene turned off: {lines:?}"
    );

    let again = make::run(&scene, &out, &to(StageId::Metrics), &mut |_| {}).unwrap();
    assert!(again.iter().all(|r| r.outcome != Outcome::Skipped || r.stage > StageId::Metrics));
    assert_eq!(verdict(&out, &again).unwrap(), lines, "the same verdict when up to date");
    std::fs::remove_dir_all(&dir).unwrap();
}
