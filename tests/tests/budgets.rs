//! Work estimates (issue 15): each stage that allocates in proportion to a scene field refuses
//! above the memory budget, before allocating, with exit code 2, the estimate, the field that
//! drives it and a value that would fit; nothing is written.

use std::fs;
use std::path::Path;

use karst_artifact::StageId;
use karst_pipeline::make::Selection;
use karst_scene::budget::Budget;
use karst_scene::{Scene, SceneView};
use karst_stage::runner::{self, Job};
use karst_stage::{Stage, StageError};
use karstgen_tests::{root, run, scratch};

/// Runs stage `S` on `scene` (with `edit` applied to its text) under `budget`; returns the
/// refusal's message.
fn refusal<S: Stage>(out: &Path, edit: (&str, &str), budget: &str) -> String {
    let scene_path = out.join("edited.toml");
    let text = fs::read_to_string(out.join("scene.toml")).unwrap();
    assert!(text.contains(edit.0), "{}", edit.0);
    fs::write(&scene_path, text.replace(edit.0, edit.1)).unwrap();
    let mut scene = Scene::load(&scene_path).unwrap();
    scene.set_budget(budget.parse::<Budget>().unwrap());
    match runner::run::<S>(&Job::new(&scene_path, &scene, out)) {
        Err(e @ StageError::BadInput(_)) => {
            assert_eq!(e.exit_code(), 2);
            e.to_string()
        }
        other => panic!("{}: expected a refusal, got {other:?}", S::ID.name()),
    }
}

#[test]
fn every_estimating_stage_refuses_with_its_field_and_a_value_that_fits() {
    let out = scratch("budgets");
    let scene = out.join("scene.toml");
    fs::copy(root().join("fixtures/scenes/tiny.toml"), &scene).unwrap();
    run(&scene, &out, &Selection { to: Some(StageId::Sdf), ..Selection::default() }).unwrap();
    let before: Vec<_> = fs::read_dir(&out).unwrap().flatten().map(|e| e.file_name()).collect();

    let k = refusal::<karst_costgraph::CostgraphStage>(&out, ("seed = 7", "seed = 7"), "512K");
    assert!(
        k.contains("edited.toml: costgraph.k = ") && k.contains("more than the memory budget of 512 KiB"),
        "{k}"
    );
    assert!(k.contains("costgraph.k = ") && k.contains("would fit"), "{k}");

    let sdf = refusal::<karst_sdf::SdfStage>(&out, ("seed = 7", "seed = 7"), "32K");
    assert!(sdf.contains("sdf.radius_scale = 1 means about") && sdf.contains("sphere candidates"), "{sdf}");

    let mesher = refusal::<karst_mesher::MesherStage>(&out, ("cell_size = 3.0", "cell_size = 0.05"), "1G");
    assert!(
        mesher.contains("mesher.cell_size = 0.05 means about") && mesher.contains("triangles"),
        "{mesher}"
    );
    assert!(mesher.contains("mesher.cell_size = ") && mesher.contains("would fit"), "{mesher}");

    let after: Vec<_> = fs::read_dir(&out).unwrap().flatten().map(|e| e.file_name()).collect();
    assert_eq!(after.len(), before.len() + 1, "only the edited scene is new: {after:?}");
    fs::remove_dir_all(&out).unwrap();
}

#[test]
fn the_mesher_s_work_estimate_is_within_a_factor_two_of_its_meshes() {
    // tiny: the uniform lattice (a plane); geotiff: the terrain lattice (20 m pixels, 4 m cells).
    for name in ["tiny", "geotiff"] {
        let out = scratch(&format!("mesh-estimate-{name}"));
        let scene_path = out.join("scene.toml");
        copy_scene(name, &scene_path);
        run(&scene_path, &out, &Selection { to: Some(StageId::Mesher), ..Selection::default() }).unwrap();
        let scene = Scene::load(&scene_path).unwrap();
        let (_, model) = karst_artifact::read_artifact::<karst_sdf::SdfModel>(&out.join("sdf.bin")).unwrap();
        let work = karst_mesher::Work::of(&karst_mesher::MesherView::of(&scene), &model);
        let (_, mesh) = karst_artifact::read_artifact::<karst_mesher::Mesh>(&out.join("mesh.bin")).unwrap();
        let triangles: usize = mesh.surfaces().iter().map(|(_, m)| m.triangles.len()).sum();
        let terrain = mesh.terrain.triangles.len() as f64;
        let bytes = fs::metadata(out.join("mesh.bin")).unwrap().len() as f64;
        let within_two = |estimate: f64, real: f64| estimate <= 2.0 * real && real <= 2.0 * estimate;
        assert!(within_two(work.triangles, triangles as f64), "{name}: {work:?} for {triangles} triangles");
        assert!(
            within_two(work.terrain_triangles, terrain),
            "{name}: {work:?} for {terrain} terrain triangles"
        );
        assert!(within_two(work.bytes, bytes), "{name}: {work:?} for {bytes} bytes of mesh.bin");
        assert!(within_two(work.cells * 2.0, triangles as f64), "{name}: {work:?} for {triangles} triangles");
        fs::remove_dir_all(&out).unwrap();
    }
}

/// Copies fixtures/scenes/NAME.toml to `to` with its data files, which it names relative to it.
fn copy_scene(name: &str, to: &Path) {
    let scenes = root().join("fixtures/scenes");
    let text = fs::read_to_string(scenes.join(format!("{name}.toml"))).unwrap();
    let data = format!("file = \"{}/data/", scenes.display());
    fs::write(to, text.replace("file = \"data/", &data)).unwrap();
}

#[test]
fn a_mesher_cell_of_five_centimetres_is_refused_before_the_mesher_runs() {
    let out = scratch("mesh-budget");
    let scene = out.join("scene.toml");
    fs::copy(root().join("fixtures/bad/mesher_cell_tiny.toml"), &scene).unwrap();
    let err = run(&scene, &out, &Selection::default()).unwrap_err();
    assert_eq!(err.exit_code(), 2, "{err}");
    let message = err.to_string();
    for part in ["scene.toml: the mesher would make about", "mesher.cell_size = 0.05 m", "budget of 300 MiB"]
    {
        assert!(message.contains(part), "{part}: {message}");
    }
    for advice in ["raise mesher.cell_size", "mesher.cave_cell_size", "--budget MB"] {
        assert!(message.contains(advice), "{advice}: {message}");
    }
    assert!(out.join("sdf.bin").is_file() && !out.join("mesh.bin").exists());
    fs::remove_dir_all(&out).unwrap();
}

#[test]
fn exports_beyond_the_budget_are_refused_before_a_file_is_written() {
    let out = scratch("export-budget");
    // tiny's meshes (full passage detail) are estimated at about 1.7 MiB (0.97 MiB written) and
    // its exports at about 2.2 MiB beside them: a 2.5 MB budget lets the mesher run and stops
    // the export.
    let budget = karst_pipeline::budget::OutputBudget::megabytes(2.5).unwrap();
    let selection = Selection { budget, ..Selection::default() };
    let err = run(&root().join("fixtures/scenes/tiny.toml"), &out, &selection).unwrap_err();
    assert_eq!(err.exit_code(), 2, "{err}");
    let message = err.to_string();
    for part in ["the export would write about", "gltf", "beside", "of mesh.bin", "budget of 2.5"] {
        assert!(message.contains(part), "{part}: {message}");
    }
    for advice in ["export.formats", "export.gltf_max_mb", "mesher.cell_size", "--budget MB"] {
        assert!(message.contains(advice), "{advice}: {message}");
    }
    assert!(
        out.join("mesh.bin").is_file() && !out.join("export.json").exists() && !out.join("export").exists()
    );
    fs::remove_dir_all(&out).unwrap();
}

#[test]
fn the_6_km_real_terrain_case_is_estimated_within_the_default_budget_before_the_mesher_runs() {
    // fixtures/bench/jacksboro-6km.toml (a 30 m DEM, 64 km of conduits, defaults): the estimate
    // the run prints before the mesher, with the automatic cave cell, under the default budget;
    // the cave cell is the passages' median half-thickness, not the 0.25 m floor its thinnest
    // pinch would give (issue 40).
    let out = scratch("jacksboro-estimate");
    let scene_path = root().join("fixtures/bench/jacksboro-6km.toml");
    run(&scene_path, &out, &Selection { to: Some(StageId::Sdf), ..Selection::default() }).unwrap();
    let scene = Scene::load(&scene_path).unwrap();
    let (_, model) = karst_artifact::read_artifact::<karst_sdf::SdfModel>(&out.join("sdf.bin")).unwrap();
    let view = karst_mesher::MesherView::of(&scene);
    let cell = view.mesher.cell_size;
    let cave = karst_mesher::cave_cell(&model, cell, view.mesher.cave_cell_size);
    assert!(cave > cell / karst_mesher::CAVE_REFINE, "cave cell {cave} m at its floor");
    let work = karst_mesher::Work::of(&view, &model);
    let budget = karst_pipeline::budget::OutputBudget::default();
    assert!(work.bytes < budget.bytes, "{work:?} beyond {budget:?}");
    // Its mesh and its glb (at most the gltf bound) leave room in the budget for the rest: with
    // the default passage detail the automatic cave cell is coarsened to half the budget
    // (`Work::planned`), which the estimate then meets to the byte.
    assert!(work.bytes <= budget.bytes / 2.0 * (1.0 + 1e-9), "{work:?}");
    fs::remove_dir_all(&out).unwrap();
}
