//! Ensembles: byte-identical outputs whatever the thread count, resumable runs, merged seed
//! ranges equal to one run, failures recorded without stopping the others, data files read
//! from the scene's folder.

use std::path::{Path, PathBuf};

use karst_artifact::StageId;
use karst_pipeline::ensemble::{self, Keep, Outcome, Plan, Record};
use karst_pipeline::scene::SceneFile;
use karst_testkit::{fixture, scratch};

const OUTPUTS: &[&str] = &[
    "metrics.csv",
    "summary.csv",
    "failures.csv",
    "probability.vti",
    "probability-top.png",
    "probability/grid.json",
];

fn plan(to: Option<StageId>, keep: Keep) -> Plan {
    let scene = SceneFile::load(&fixture("fixtures/scenes/tiny.toml")).unwrap();
    Plan::new(scene, to, 20.0, keep).unwrap()
}

/// Every summary output of `out` (slices included), by name.
fn outputs(out: &Path) -> Vec<(String, Vec<u8>)> {
    let mut files: Vec<PathBuf> = OUTPUTS.iter().map(|f| out.join(f)).collect();
    files.extend(
        std::fs::read_dir(out.join("probability"))
            .unwrap()
            .map(|e| e.unwrap().path())
            .filter(|p| p.extension().is_some_and(|e| e == "exr")),
    );
    files.sort();
    files
        .into_iter()
        .map(|f| (f.strip_prefix(out).unwrap().display().to_string(), std::fs::read(f).unwrap()))
        .collect()
}

fn assert_same(a: &[(String, Vec<u8>)], b: &[(String, Vec<u8>)], what: &str) {
    assert_eq!(a.len(), b.len(), "{what}: different files");
    for ((name, x), (other, y)) in a.iter().zip(b) {
        assert_eq!(name, other);
        assert!(x == y, "{name} differs ({what})");
    }
}

#[test]
fn outputs_do_not_depend_on_the_thread_count_and_a_rerun_does_no_work() {
    let base = scratch("ensemble-threads");
    let plan = plan(None, Keep::Stages(vec![StageId::Skeleton]));
    let seeds = [3, 4, 5];
    let run_with = |threads: usize, out: &Path| {
        let pool = rayon::ThreadPoolBuilder::new().num_threads(threads).build().unwrap();
        pool.install(|| ensemble::run(&plan, out, &seeds, None)).unwrap()
    };
    let one = run_with(1, &base.join("one"));
    run_with(2, &base.join("two"));
    assert_eq!((one.ran, one.complete, one.failures.len()), (3, 3, 0));
    assert_same(&outputs(&base.join("one")), &outputs(&base.join("two")), "1 vs 2 threads");

    let csv = std::fs::read_to_string(base.join("one/metrics.csv")).unwrap();
    let seeds_read: Vec<&str> = csv.lines().skip(1).map(|l| l.split(',').next().unwrap()).collect();
    assert_eq!(seeds_read, ["3", "4", "5"]);
    let header = csv.lines().next().unwrap();
    for column in
        ["\"aspl\"", "\"vadose length\"", "\"tube length\"", "\"stream water length\"", "discharge (m3/s)"]
    {
        assert!(header.contains(column), "{column} missing from {header}");
    }
    // The whole pipeline ran; only the skeleton and the record stay.
    let mut kept: Vec<String> = std::fs::read_dir(base.join("one/realizations/seed-4"))
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    kept.sort();
    assert_eq!(kept, ["record.json", "skeleton.json"]);

    let record = base.join("one/realizations/seed-4/record.json");
    let before = std::fs::metadata(&record).unwrap().modified().unwrap();
    let again = ensemble::run(&plan, &base.join("one"), &seeds, None).unwrap();
    assert_eq!((again.ran, again.complete), (0, 3));
    assert_eq!(std::fs::metadata(&record).unwrap().modified().unwrap(), before, "the record was rewritten");
    std::fs::remove_dir_all(&base).unwrap();
}

#[test]
fn seed_ranges_merged_equal_one_run() {
    let base = scratch("ensemble-merge");
    let plan = plan(Some(StageId::Skeleton), Keep::Stages(vec![]));
    ensemble::run(&plan, &base.join("all"), &[1, 2, 3, 4], None).unwrap();
    ensemble::run(&plan, &base.join("a"), &[1, 2], None).unwrap();
    ensemble::run(&plan, &base.join("b"), &[3, 4, 2], None).unwrap();
    let merged = ensemble::merge(&[base.join("a"), base.join("b")], &base.join("merged"), None).unwrap();
    assert_eq!((merged.ran, merged.complete), (0, 4));
    assert_same(&outputs(&base.join("all")), &outputs(&base.join("merged")), "merged vs one run");
    let header = std::fs::read_to_string(base.join("all/metrics.csv")).unwrap();
    assert!(!header.contains("water length"), "no hydro columns without hydro");

    // Another plan's folder is neither reused nor merged.
    let other =
        Plan::new(SceneFile::load(&fixture("fixtures/scenes/tiny.toml")).unwrap(), None, 20.0, Keep::All)
            .unwrap();
    let e = ensemble::run(&other, &base.join("a"), &[1], None).unwrap_err().to_string();
    assert!(e.contains("another scene or other settings"), "{e}");
    ensemble::run(&other, &base.join("c"), &[1], None).unwrap();
    let e =
        ensemble::merge(&[base.join("a"), base.join("c")], &base.join("m2"), None).unwrap_err().to_string();
    assert!(e.contains("another scene or other settings"), "{e}");
    std::fs::remove_dir_all(&base).unwrap();
}

#[test]
fn a_failing_realization_is_recorded_and_the_others_complete() {
    let out = scratch("ensemble-failure");
    let plan = plan(Some(StageId::Skeleton), Keep::Stages(vec![]));
    // A folder where seed 2's samples.bin must go: its sampling stage cannot write it.
    std::fs::create_dir_all(out.join("realizations/seed-2/samples.bin/blocked")).unwrap();
    let summary = ensemble::run(&plan, &out, &[1, 2, 3], None).unwrap();
    assert_eq!(summary.complete, 2);
    assert_eq!(summary.failures.len(), 1);
    assert_eq!(summary.failures[0].0, 2);
    let failures = std::fs::read_to_string(out.join("failures.csv")).unwrap();
    assert!(failures.starts_with("seed,error\n2,\"") && failures.contains("samples.bin"), "{failures}");
    let record = Record::read(&Record::path(&out, 2)).unwrap();
    assert!(matches!(record.outcome, Outcome::Failed { retry: true, .. }), "{record:?}");
    // A machine failure is tried again on the next run; once it can, it completes.
    std::fs::remove_dir_all(out.join("realizations/seed-2/samples.bin")).unwrap();
    let again = ensemble::run(&plan, &out, &[1, 2, 3], None).unwrap();
    assert_eq!((again.ran, again.complete, again.failures.len()), (1, 3, 0));
    std::fs::remove_dir_all(&out).unwrap();
}

#[test]
fn data_files_are_read_from_the_scene_folder() {
    // The default scene names a heightfield and a TSurf relative to its own folder.
    let out = scratch("ensemble-data");
    let scene = SceneFile::load(&fixture("fixtures/scenes/default.toml")).unwrap();
    let plan = Plan::new(scene, Some(StageId::Skeleton), 25.0, Keep::Stages(vec![])).unwrap();
    let summary = ensemble::run(&plan, &out, &[11], None).unwrap();
    assert_eq!((summary.complete, summary.failures.len()), (1, 0), "{:?}", summary.failures);
    std::fs::remove_dir_all(&out).unwrap();
}
