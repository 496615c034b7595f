//! The tiny scene's artifacts are pinned in fixtures/golden/tiny: a change in any stage's output
//! shows here (rerun `cargo xtask bless` and explain the change in the commit). With `[sdf]
//! passage_detail = "off"` its skeleton and sdf are pinned in fixtures/golden/tiny-off: the
//! artifacts of karstgen before passage detail, which `off` promises byte for byte (rerun with
//! `KARSTGEN_BLESS_OFF=1` to rewrite them, and say why in the commit).

use karst_artifact::StageId;
use karst_pipeline::diff;
use karst_pipeline::make::Selection;
use karstgen_tests::{artifacts, root, run, run_with_threads, scratch};

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
fn passage_detail_off_writes_the_skeleton_and_sdf_of_before() {
    let out = scratch("golden-off");
    let text = std::fs::read_to_string(root().join("fixtures/scenes/tiny.toml")).unwrap();
    assert!(!text.contains("\n[sdf]"), "tiny has its own [sdf]: set passage_detail in it");
    let scene = out.join("tiny-off.toml");
    std::fs::write(&scene, format!("{text}\n[sdf]\npassage_detail = \"off\"\n")).unwrap();
    run(&scene, &out, &Selection { to: Some(StageId::Sdf), ..Selection::default() }).unwrap();
    let golden = root().join("fixtures/golden/tiny-off");
    let bless = std::env::var_os("KARSTGEN_BLESS_OFF").is_some();
    for stage in [StageId::Skeleton, StageId::Sdf] {
        let (pinned, made) = (golden.join(stage.file_name()), out.join(stage.file_name()));
        if bless {
            std::fs::copy(&made, &pinned).unwrap();
        }
        assert!(
            std::fs::read(&pinned).unwrap() == std::fs::read(&made).unwrap(),
            "{} with passage_detail = \"off\" differs from {}:\n{}",
            stage.file_name(),
            pinned.display(),
            diff::diff(&pinned, &made, 1e-9).unwrap().summary()
        );
    }
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

/// The `| `tiny/NAME` | `HASH` |` rows of the last entry of fixtures/golden/CHANGES.md.
fn last_recorded_hashes(changes: &str) -> Vec<(String, String)> {
    let last = changes.rsplit("\n## ").next().unwrap_or_default();
    let mut rows: Vec<(String, String)> = last
        .lines()
        .filter_map(|line| {
            let cells: Vec<&str> = line.split('|').map(|c| c.trim().trim_matches('`')).collect();
            match cells.as_slice() {
                ["", name, hash, ""] if name.starts_with("tiny/") => {
                    Some((name.to_string(), hash.to_string()))
                }
                _ => None,
            }
        })
        .collect();
    rows.sort();
    rows
}

/// Every golden of fixtures/golden/tiny as recorded by the last `cargo xtask bless --accept`:
/// a golden replaced without the review and its reason fails here.
#[test]
fn the_goldens_are_those_changes_md_records_last() {
    let golden = root().join("fixtures/golden");
    let changes = std::fs::read_to_string(golden.join("CHANGES.md")).unwrap();
    let mut files: Vec<(String, String)> = std::fs::read_dir(golden.join("tiny"))
        .unwrap()
        .map(|e| {
            let path = e.unwrap().path();
            let name = format!("tiny/{}", path.file_name().unwrap().to_string_lossy());
            (name, blake3::hash(&std::fs::read(&path).unwrap()).to_hex().to_string())
        })
        .collect();
    files.sort();
    assert_eq!(files.len(), 10, "one golden per stage");
    assert_eq!(
        last_recorded_hashes(&changes),
        files,
        "fixtures/golden/tiny differs from the last entry of fixtures/golden/CHANGES.md: bless with \
         `cargo xtask bless --accept --why REASON`"
    );
    let tampered = changes.replace(&files[0].1, &"0".repeat(64));
    assert_ne!(last_recorded_hashes(&tampered), files, "the check sees a changed hash");
}
