//! Every scene of `fixtures/scenes/` (each `*.toml`, found at run time, so new presets are
//! covered without editing this test) is run through sampling, costgraph, skeleton and metrics
//! in process; karstnet 1.2.5 then characterises the skeleton's karstnet export
//! (`network_nodes.dat` / `network_links.dat`) and must agree with `metrics.json` and with
//! `characterize` on the export, every key within 1e-9 relative.
//!
//! Needs `KARSTNET_PYTHON` (set by `cargo xtask test`): without it, or with a broken karstnet, the
//! test fails loudly.

mod common;

use std::path::{Path, PathBuf};

use common::{as_map, assert_same, json_map, karstnet_metrics, python};
use karst_artifact::read_artifact;
use karst_metrics::MetricsReport;
use karst_metrics::characterize;
use karst_metrics::readers::read_karstnet;
use karst_testkit::scratch;

fn scenes() -> Vec<PathBuf> {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../fixtures/scenes");
    let mut scenes: Vec<PathBuf> = std::fs::read_dir(&dir)
        .unwrap_or_else(|e| panic!("{}: {e}", dir.display()))
        .map(|entry| entry.expect("readable folder").path())
        .filter(|p| p.extension().is_some_and(|e| e == "toml"))
        .collect();
    scenes.sort();
    scenes
}

fn run_stages(scene: &Path, out: &Path) {
    let args = (scene.to_path_buf(), out.to_path_buf());
    let name = scene.display();
    karst_testkit::run::<karst_sampling::SamplingStage>(&args.0, &args.1)
        .unwrap_or_else(|e| panic!("{name}: sampling: {e}"));
    karst_testkit::run::<karst_costgraph::CostgraphStage>(&args.0, &args.1)
        .unwrap_or_else(|e| panic!("{name}: costgraph: {e}"));
    karst_testkit::run::<karst_skeleton::SkeletonStage>(&args.0, &args.1)
        .unwrap_or_else(|e| panic!("{name}: skeleton: {e}"));
    karst_testkit::run::<karst_hydro::HydroStage>(&args.0, &args.1)
        .unwrap_or_else(|e| panic!("{name}: hydro: {e}"));
    karst_testkit::run::<karst_streams::StreamsStage>(&args.0, &args.1)
        .unwrap_or_else(|e| panic!("{name}: streams: {e}"));
    // The metrics read the survey of the carved passages (survey.json), which reads sdf.bin.
    karst_testkit::run::<karst_sdf::SdfStage>(&args.0, &args.1)
        .unwrap_or_else(|e| panic!("{name}: sdf: {e}"));
    karst_testkit::run::<karst_survey::SurveyStage>(&args.0, &args.1)
        .unwrap_or_else(|e| panic!("{name}: survey: {e}"));
    karst_testkit::run::<karst_metrics::MetricsStage>(&args.0, &args.1)
        .unwrap_or_else(|e| panic!("{name}: metrics: {e}"));
}

#[test]
fn every_scene_matches_karstnet() {
    let python = python();
    let scenes = scenes();
    assert!(scenes.len() >= 2, "fixtures/scenes holds at least default and tiny");
    for scene in scenes {
        let name = scene.file_stem().expect("a file name").to_string_lossy().into_owned();
        let out = scratch(&format!("scene-{name}"));
        run_stages(&scene, &out);
        let base = out.join(karst_skeleton::stage::KARSTNET_BASE);
        let theirs = json_map(&karstnet_metrics(&python, &base));
        let exported = characterize(&read_karstnet(&base).expect("the export reads")).expect("valid");
        assert_same(&as_map(&exported), &theirs, 1e-9, &[], &format!("{name} (export)"));
        let (_, report) = read_artifact::<MetricsReport>(&out.join("metrics.json")).expect("metrics.json");
        assert_same(&as_map(&report.network), &theirs, 1e-9, &[], &format!("{name} (metrics.json)"));
        // Every segment is counted once under its water type, and under its conduit type.
        let total = report.network.total_length;
        for (what, lengths) in [("water", &report.water_types), ("conduit", &report.conduit_types)] {
            let sum: f64 = lengths.values().sum();
            assert!((sum - total).abs() <= 1e-9 * total, "{name}: {what} types sum to {sum}, total {total}");
        }
        for (key, compared) in &report.karstnet {
            assert!(common::close(compared.value, theirs[key], 1e-9), "{name}: {key}");
        }
        eprintln!(
            "{name}: {} nodes, {} branches, {} of 10 metrics within real caves: karstnet agrees",
            report.network.n_nodes_full,
            report.network.n_branches,
            report.karstnet.values().filter(|c| c.inside).count()
        );
        std::fs::remove_dir_all(out).expect("remove temp dir");
    }
}
