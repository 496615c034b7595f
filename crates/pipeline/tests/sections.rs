//! The key of every artifact hashes exactly the scene sections its stage reads: each stage is
//! run on audited scenes (every section handed out is recorded) and what it read is compared
//! with its row of the stage table, in both directions. A stage that reads a section it does
//! not declare would leave a stale artifact "up to date" when that section changes; a declared
//! section it never reads would rerun it for nothing.

use std::collections::{BTreeMap, BTreeSet};

use karst_artifact::StageId;
use karst_geology::{Scene, Section};
use karst_pipeline::registry;
use karst_pipeline::scene::SceneFile;
use karst_stage::Job;
use karst_testkit::{fixture, scratch};

/// The scenes audited (a scene file, TOML appended to it) and the stages run on each: together
/// they take every branch that reads a section (KarstNSim and Paris costs, phases, horizons, a
/// heightfield terrain, catchment recharge, GeoTIFF rasters, a lithology grid and a key-point
/// table).
const CASES: &[(&str, &str, &[StageId])] = &[
    ("fixtures/scenes/tiny.toml", "", &StageId::ALL),
    ("fixtures/scenes/default.toml", "", &StageId::ALL),
    ("fixtures/scenes/looping.toml", "", &[StageId::Sampling, StageId::Costgraph]),
    ("fixtures/scenes/karstnsim-2phase.toml", "", UP_TO_HYDRO),
    ("fixtures/scenes/geotiff.toml", "", UP_TO_HYDRO),
    ("fixtures/scenes/tiny.toml", "[hydro]\nrecharge = \"catchment\"\n", UP_TO_HYDRO),
];

const UP_TO_HYDRO: &[StageId] = &[StageId::Sampling, StageId::Costgraph, StageId::Skeleton, StageId::Hydro];

/// The scene of `path` with `extra` appended (data files still relative to its folder).
fn scene(path: &str, extra: &str) -> SceneFile {
    let path = fixture(path);
    let text = std::fs::read_to_string(&path).unwrap() + "\n" + extra;
    SceneFile { scene: Scene::parse(&text, &path).unwrap(), path }
}

#[test]
fn every_stage_reads_exactly_the_sections_it_declares() {
    let mut read: BTreeMap<StageId, BTreeSet<&str>> = BTreeMap::new();
    for (path, extra, stages) in CASES {
        let scene = scene(path, extra);
        let out = scratch("sections");
        for &stage in *stages {
            let audited = scene.scene.audited();
            let job = Job::new(&scene.path, &audited, &out);
            registry::stage(stage).run(&job).unwrap_or_else(|e| panic!("{path}: {}: {e}", stage.name()));
            let sections: BTreeSet<&str> = audited.sections_read().into_iter().map(Section::key).collect();
            let declared: BTreeSet<&str> = stage.row().sections.iter().copied().collect();
            let undeclared: Vec<&&str> = sections.difference(&declared).collect();
            assert!(
                undeclared.is_empty(),
                "{path}: {} reads {undeclared:?} without declaring it",
                stage.name()
            );
            read.entry(stage).or_default().extend(sections);
        }
        std::fs::remove_dir_all(&out).unwrap();
    }
    for stage in StageId::ALL {
        let declared: BTreeSet<&str> = stage.row().sections.iter().copied().collect();
        let unread: Vec<&&str> = declared.difference(&read[&stage]).collect();
        assert!(
            unread.is_empty(),
            "{} declares {unread:?} but no audited scene made it read them",
            stage.name()
        );
    }
}

#[test]
fn every_declared_section_is_a_section_of_the_scene() {
    for stage in StageId::ALL {
        for key in stage.row().sections {
            assert!(Section::from_key(key).is_some(), "{}: no scene section {key}", stage.name());
        }
    }
}
