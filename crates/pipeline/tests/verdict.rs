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

/// tiny with `[calibrate] like = NAME` and the even branches of [`EVEN`].
fn tiny_like(dir: &std::path::Path, like: &str) -> std::path::PathBuf {
    let text = std::fs::read_to_string(fixture("fixtures/scenes/tiny.toml")).unwrap();
    let path = dir.join("scene.toml");
    std::fs::write(
        &path,
        format!("{}\n[calibrate]\nlike = \"{like}\"\n", text.replacen("[skeleton]\n", EVEN, 1)),
    )
    .unwrap();
    path
}

#[test]
fn a_calibrated_scene_reports_against_its_target() {
    let dir = scratch("verdict-target");
    let scene = SceneFile::load(&tiny_like(&dir, "Sakany")).unwrap();
    let out = dir.join("out");
    let to = Selection { to: Some(StageId::Metrics), ..Selection::default() };
    let reports = make::run(&scene, &out, &to, &mut |_| {}).unwrap();
    let lines = verdict(&out, &reports).unwrap();
    assert!(
        lines[0].starts_with("verdict: ") && lines[0].contains(" on target (Sakany), distance "),
        "{lines:?}"
    );
    assert!(lines[0].ends_with(" inside real-cave ranges"), "{lines:?}");
    let (_, report) = karst_artifact::read_artifact::<karst_metrics::MetricsReport>(
        &out.join(StageId::Metrics.file_name()),
    )
    .unwrap();
    let target = report.target.as_ref().expect("the report holds the target");
    let sakany = karst_metrics::aim::like("Sakany").unwrap();
    assert_eq!(target.name, "Sakany");
    assert_eq!(
        lines.len() - 1,
        target.defined - target.on_target,
        "one hint per metric off target: {lines:?}"
    );
    // Every hint points from the run's value towards Sakany's, by the sign of the difference.
    for line in &lines[1..] {
        let hint = line.strip_prefix("  hint: ").unwrap();
        let (i, key) = karst_metrics::ranges::CHARACTERIZE_KEYS
            .iter()
            .enumerate()
            .find(|(_, k)| hint.starts_with(&format!("{k} ")))
            .unwrap_or_else(|| panic!("{hint}"));
        let value = report.karstnet[*key].value;
        let sign = if value > sakany.statistics[i] { ">" } else { "<" };
        assert!(hint.contains(&format!(" {sign} ")) && hint.contains(" of Sakany ("), "{hint}");
        assert!(
            hint.contains(" — skeleton.") || hint.contains(" — sampling."),
            "names the parameter: {hint}"
        );
    }
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn an_unknown_like_in_the_scene_exits_2_naming_the_field() {
    let dir = scratch("verdict-unknown");
    let path = tiny_like(&dir, "Lascaux");
    let e = SceneFile::load(&path).unwrap_err();
    assert_eq!(e.exit_code(), 2, "{e}");
    let message = e.to_string();
    assert!(message.contains("scene.toml") && message.contains("calibrate.like = \"Lascaux\""), "{message}");
    assert!(message.contains("Sakany"), "lists the names: {message}");
    let both = dir.join("both.toml");
    let text = std::fs::read_to_string(&path)
        .unwrap()
        .replace("like = \"Lascaux\"", "like = \"Sakany\"\ntarget = \"x.pl\"");
    std::fs::write(&both, text).unwrap();
    let message = SceneFile::load(&both).unwrap_err().to_string();
    assert!(message.contains("calibrate.target") && message.contains("not both"), "{message}");
    std::fs::remove_dir_all(&dir).unwrap();
}
