//! make-like staleness: up-to-date stages are skipped, editing a section reruns only the stages
//! that read it and those downstream, and a corrupted input stops the next stage.

use std::fs;

use karst_artifact::StageId;
use karst_pipeline::make::{Outcome, Selection};
use karst_stage::StageError;
use karstgen_tests::{root, run, scratch};

fn ran(reports: &[karst_pipeline::make::StageReport]) -> Vec<StageId> {
    reports.iter().filter(|r| matches!(r.outcome, Outcome::Ran { .. })).map(|r| r.stage).collect()
}

#[test]
fn second_run_is_up_to_date_and_edits_rerun_the_stages_that_read_them() {
    let out = scratch("stale");
    let scene = out.join("scene.toml");
    let text = fs::read_to_string(root().join("fixtures/scenes/tiny.toml")).unwrap();
    fs::write(&scene, &text).unwrap();
    let first = run(&scene, &out, &Selection::default()).unwrap();
    assert_eq!(ran(&first), StageId::ALL.to_vec());
    let second = run(&scene, &out, &Selection::default()).unwrap();
    assert!(second.iter().all(|r| r.outcome == Outcome::UpToDate), "{second:?}");

    fs::write(&scene, format!("{text}\n[sdf]\nradius_scale = 1.25\n")).unwrap();
    let third = run(&scene, &out, &Selection::default()).unwrap();
    // The survey measures the carved passages and the metrics read it.
    assert_eq!(
        ran(&third),
        vec![StageId::Sdf, StageId::Mesher, StageId::Survey, StageId::Metrics, StageId::Export]
    );

    // [streams] is read by streams and sdf; the banks' slope leaves streams.json as it was, so
    // the metrics (which read streams.json) stay up to date; the runoff changes the flows.
    let streams = |s: &str| format!("{text}\n[sdf]\nradius_scale = 1.25\n[streams]\n{s}\n");
    // survey.json's payload, after its header line (whose key follows sdf.bin's bytes).
    let survey = || {
        let bytes = fs::read(out.join(StageId::Survey.file_name())).unwrap();
        bytes[bytes.iter().position(|&b| b == b'\n').unwrap()..].to_vec()
    };
    let surveyed = survey();
    fs::write(&scene, streams("bank_slope = 0.8")).unwrap();
    let fourth = run(&scene, &out, &Selection::default()).unwrap();
    // The survey remeasures the carved passages; the metrics rerun exactly when it found them
    // changed (where a stream's banks are carved into a surveyed passage).
    let mut expected =
        vec![StageId::Streams, StageId::Sdf, StageId::Mesher, StageId::Survey, StageId::Export];
    if survey() != surveyed {
        expected.insert(4, StageId::Metrics);
    }
    assert_eq!(ran(&fourth), expected);
    fs::write(&scene, streams("bank_slope = 0.8\nrunoff = 900")).unwrap();
    let fifth = run(&scene, &out, &Selection::default()).unwrap();
    assert_eq!(
        ran(&fifth),
        vec![
            StageId::Streams,
            StageId::Sdf,
            StageId::Mesher,
            StageId::Survey,
            StageId::Metrics,
            StageId::Export
        ]
    );

    let only = run(&scene, &out, &Selection { only: Some(StageId::Hydro), ..Selection::default() }).unwrap();
    assert_eq!(ran(&only), vec![StageId::Hydro]);
    let from = run(&scene, &out, &Selection { from: Some(StageId::Mesher), ..Selection::default() }).unwrap();
    assert_eq!(ran(&from), vec![StageId::Mesher, StageId::Survey, StageId::Metrics, StageId::Export]);
}

#[test]
fn flipped_byte_in_samples_stops_costgraph_with_a_checksum_error() {
    let out = scratch("flip");
    let scene = root().join("fixtures/scenes/tiny.toml");
    run(&scene, &out, &Selection::default()).unwrap();
    let samples = out.join("samples.bin");
    let mut bytes = fs::read(&samples).unwrap();
    let last = bytes.len() - 10;
    bytes[last] ^= 0x01;
    fs::write(&samples, bytes).unwrap();
    let err =
        run(&scene, &out, &Selection { from: Some(StageId::Costgraph), ..Selection::default() }).unwrap_err();
    let StageError::BadInput(message) = err else { panic!("expected bad input, got {err}") };
    let message = message.to_string();
    assert!(message.contains("samples.bin") && message.contains("checksum"), "{message}");
    // The previous costgraph artifact is still there and intact.
    karst_artifact::read_artifact::<karst_costgraph::CostGraph>(&out.join("costgraph.bin")).unwrap();
}
