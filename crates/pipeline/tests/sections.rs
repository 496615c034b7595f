//! The key of every artifact covers exactly the scene sections its stage reads.
//!
//! A stage reads the scene only through its view (`karst_scene::view!`), whose sections are
//! the ones its key hashes, so the two cannot differ. What can still go wrong is the hashing:
//! a section whose value the hash does not see, a view whose hash differs from the scene's
//! hash of the same sections, or a stage the registry gives the wrong sections. These tests
//! edit every section of a scene, one at a time, and check which stages the edit makes stale,
//! through the same keys `karstgen run` compares.

use std::collections::BTreeMap;

use karst_artifact::StageId;
use karst_geology::{Surface, Terrain};
use karst_pipeline::make::{self, Outcome, Selection};
use karst_pipeline::registry;
use karst_pipeline::scene::SceneFile;
use karst_scene::params::{CalibrateParams, ExportFormat};
use karst_scene::{Phase, Scene, SceneView, Section};
use karst_stage::Job;
use karst_testkit::{fixture, scratch};

/// The scene with `section` changed (to a value that serializes differently), and the
/// sections whose value the change changes: a field of a section changes the section too.
fn edited(scene: &Scene, section: Section) -> (Scene, Vec<Section>) {
    let mut s = scene.clone();
    let mut changed = vec![section];
    match section {
        Section::Seed => s.set_seed(scene.seed() + 1),
        Section::Domain => s.domain_mut().max[2] += 1.0,
        Section::Terrain => {
            *s.terrain_mut() = Terrain::Plane { elevation: 1.0, origin: [0.0; 2], gradient: [0.0; 2] }
        }
        Section::Geology => s.geology_mut().horizons.push(Surface::plane("extra", 1.0, [0.0; 2], 0.0, 0.0)),
        Section::Keypoints => s.keypoints_mut()[0].weight += 1.0,
        Section::Connectivity => {
            s.connectivity_mut().named.insert("sink".into(), BTreeMap::new());
        }
        Section::Phases => s.phases_mut().push(Phase {
            name: "p".into(),
            springs: Vec::new(),
            inherited_cost: 1.0,
            weights: BTreeMap::new(),
        }),
        Section::Sampling => s.sampling_mut().radius = Some(s.sampling().radius.unwrap_or(20.0) * 1.5),
        Section::Costgraph => s.costgraph_mut().k += 1,
        Section::Skeleton => s.skeleton_mut().gamma += 1.0,
        Section::ForcedLinks => {
            s.skeleton_mut().forced_links.push(["a".into(), "b".into()]);
            changed.push(Section::Skeleton);
        }
        Section::Hydro => s.hydro_mut().catchment_cell *= 2.0,
        Section::TotalDischarge => {
            s.hydro_mut().total_discharge *= 2.0;
            changed.push(Section::Hydro);
        }
        Section::Streams => s.streams_mut().step *= 2.0,
        Section::Sdf => s.sdf_mut().radius_scale *= 1.25,
        Section::PassageDetail => {
            s.sdf_mut().passage_detail = karst_scene::params::PassageDetail::Passages;
            changed.push(Section::Sdf);
        }
        Section::Mesher => s.mesher_mut().cell_size *= 2.0,
        Section::Export => {
            let formats = &mut s.export_mut().formats;
            if formats.is_empty() { formats.push(ExportFormat::Csv) } else { formats.clear() }
        }
        Section::Calibrate => *s.calibrate_mut() = Some(CalibrateParams::default()),
        Section::CalibrationAim => {
            *s.calibrate_mut() =
                Some(CalibrateParams { like: Some("Sakany".into()), ..CalibrateParams::default() });
            changed.push(Section::Calibrate);
        }
    }
    (s, changed)
}

/// The stages that read any of `sections`.
fn readers(sections: &[Section]) -> Vec<StageId> {
    StageId::ALL
        .into_iter()
        .filter(|id| registry::stage(*id).sections().iter().any(|s| sections.contains(s)))
        .collect()
}

fn tiny() -> SceneFile {
    SceneFile::load(&fixture("fixtures/scenes/tiny.toml")).unwrap()
}

#[test]
fn editing_a_section_makes_stale_exactly_the_stages_whose_view_holds_it() {
    let scene = tiny();
    let out = scratch("sections");
    make::run(&scene, &out, &Selection::default(), &mut |_| {}).unwrap();
    let job = Job::new(&scene.path, &scene.scene, &out);
    assert!(StageId::ALL.into_iter().all(|id| make::up_to_date(&job, id)));
    for section in Section::ALL {
        let (edited, changed) = edited(&scene.scene, section);
        let job = Job::new(&scene.path, &edited, &out);
        // Only the keys are compared: upstream artifacts are those of the unedited scene.
        let stale: Vec<StageId> =
            StageId::ALL.into_iter().filter(|id| !make::up_to_date(&job, *id)).collect();
        assert_eq!(stale, readers(&changed), "editing {}", section.key());
    }
    // Every section some stage reads, and only `[calibrate]` read by none.
    let unread: Vec<Section> = Section::ALL.into_iter().filter(|s| readers(&[*s]).is_empty()).collect();
    assert_eq!(unread, [Section::Calibrate]);
    std::fs::remove_dir_all(&out).unwrap();
}

#[test]
fn an_edit_outside_a_view_leaves_its_stage_up_to_date_and_one_inside_reruns_it() {
    let tiny = tiny();
    let out = scratch("sections-run");
    let ran = |scene: &Scene| -> Vec<StageId> {
        let file = SceneFile { path: tiny.path.clone(), scene: scene.clone() };
        let reports = make::run(&file, &out, &Selection::default(), &mut |_| {}).unwrap();
        reports.iter().filter(|r| matches!(r.outcome, Outcome::Ran { .. })).map(|r| r.stage).collect()
    };
    assert_eq!(ran(&tiny.scene), StageId::ALL);
    // `[mesher]` is in the mesher's view only: it and the export (which reads mesh.bin) rerun.
    let (scene, _) = edited(&tiny.scene, Section::Mesher);
    assert_eq!(ran(&scene), [StageId::Mesher, StageId::Export]);
    // `[calibrate]` is in no view: nothing reruns.
    let (scene, _) = edited(&scene, Section::Calibrate);
    assert_eq!(ran(&scene), []);
    // `hydro.total_discharge` is in the streams' view on its own, and in the hydro's `[hydro]`.
    let (scene, _) = edited(&scene, Section::TotalDischarge);
    assert_eq!(ran(&scene)[..2], [StageId::Hydro, StageId::Streams]);
    std::fs::remove_dir_all(&out).unwrap();
}

/// Each view's own hash (what the cost graph records as `made_under` and the skeleton checks)
/// equals the scene's hash of the view's sections, on scenes that use every kind of input.
#[test]
fn a_view_hashes_its_sections_as_the_scene_does() {
    macro_rules! check {
        ($scene:expr, $($view:ty),*) => {$(
            assert_eq!(
                <$view>::of($scene).sections_hash(),
                $scene.sections_hash(<$view>::SECTIONS),
                "{}: {}",
                $scene.name(),
                stringify!($view)
            );
        )*};
    }
    for name in ["tiny", "default", "karstnsim-2phase", "geotiff", "layered", "waterfall"] {
        let mut scene = SceneFile::load(&fixture(&format!("fixtures/scenes/{name}.toml"))).unwrap().scene;
        for edit in [false, true] {
            if edit {
                scene.skeleton_mut().forced_links.push(["a".into(), "b".into()]);
                *scene.calibrate_mut() = Some(CalibrateParams::default());
            }
            check!(
                &scene,
                karst_sampling::SamplingView,
                karst_costgraph::CostgraphView,
                karst_skeleton::SkeletonView,
                karst_hydro::HydroView,
                karst_streams::StreamsView,
                karst_sdf::SdfView,
                karst_mesher::MesherView,
                karst_metrics::MetricsView,
                karst_export::ExportView
            );
        }
        // The skeleton costs edges under the cost graph's sections, taken from its own view.
        let skeleton = karst_skeleton::SkeletonView::of(&scene);
        assert_eq!(
            skeleton.costs().sections_hash(),
            scene.sections_hash(karst_costgraph::CostgraphView::SECTIONS)
        );
    }
}

#[test]
fn every_stage_has_the_sections_of_its_view() {
    for id in StageId::ALL {
        let sections = registry::stage(id).sections();
        let mut unique = sections.to_vec();
        unique.sort();
        unique.dedup();
        assert_eq!(unique.len(), sections.len(), "{}: a section twice", id.name());
    }
    assert_eq!(registry::stage(StageId::Metrics).sections(), karst_metrics::MetricsView::SECTIONS);
    assert_eq!(registry::stage(StageId::Hydro).sections(), karst_hydro::HydroView::SECTIONS);
}
