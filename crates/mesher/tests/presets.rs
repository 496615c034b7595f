//! Every scene of fixtures/scenes, run through the upstream stages and meshed: its carved
//! terrain, cave and water are closed, 2-manifold, consistently oriented, free of degenerate
//! triangles and enclose a positive volume. The cells are coarser than the scenes' own (the
//! terrain at its scene's cell, the cave and water at 1 m) to keep the test short; the lattice
//! and the polygonizer are the same at every resolution.

use karst_artifact::read_artifact;
use karst_mesher::anchors;
use karst_mesher::mesh_with;
use karst_mesher::{TriMesh, watertight};
use karst_scene::Scene;
use karst_sdf::{CarvedTerrain, SdfModel};
use karst_testkit::{root, scratch};

/// The cell of the cave alone and of the water in this test, metres.
const CAVE_CELL: f64 = 1.0;

/// The scene's sdf model, its upstream stages run into a scratch folder.
fn preset_model(name: &str) -> (Scene, SdfModel) {
    let scene = root().join(format!("fixtures/scenes/{name}.toml"));
    let out = scratch(&format!("mesher-{name}"));
    let args = (scene.clone(), out.to_path_buf());
    karst_testkit::run::<karst_sampling::SamplingStage>(&args.0, &args.1).unwrap();
    karst_testkit::run::<karst_costgraph::CostgraphStage>(&args.0, &args.1).unwrap();
    karst_testkit::run::<karst_skeleton::SkeletonStage>(&args.0, &args.1).unwrap();
    karst_testkit::run::<karst_hydro::HydroStage>(&args.0, &args.1).unwrap();
    karst_testkit::run::<karst_streams::StreamsStage>(&args.0, &args.1).unwrap();
    karst_testkit::run::<karst_sdf::SdfStage>(&args.0, &args.1).unwrap();
    let (_, model): (_, SdfModel) = read_artifact(&out.join("sdf.bin")).unwrap();
    (Scene::load(&scene).unwrap(), model)
}

fn defects(name: &str, surface: &TriMesh) -> Option<String> {
    if surface.triangles.is_empty() {
        return Some(format!("{name}: empty"));
    }
    if let Err(defect) = watertight::check(surface) {
        return Some(format!("{name}: {defect}"));
    }
    let volume = surface.enclosed_volume();
    (volume <= 0.0).then(|| format!("{name}: enclosed volume {volume}"))
}

fn check_preset(name: &str) {
    let (scene, model) = preset_model(name);
    let field = CarvedTerrain::new(model);
    let mesh = mesh_with(&field, scene.mesher().cell_size, CAVE_CELL, &anchors(scene.keypoints()));
    let failures: Vec<String> = [("terrain", &mesh.terrain), ("cave", &mesh.cave), ("water", &mesh.water)]
        .into_iter()
        .filter_map(|(surface, s)| defects(&format!("{name} {surface}"), s))
        .collect();
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}

macro_rules! preset_tests {
    ($($(#[$attribute:meta])* $test:ident: $name:literal;)*) => {
        $(
            #[test]
            $(#[$attribute])*
            fn $test() {
                check_preset($name);
            }
        )*

        /// Every fixtures/scenes/*.toml scene has its test above.
        #[test]
        fn every_scene_is_meshed() {
            let tested = [$($name),*];
            for entry in std::fs::read_dir(root().join("fixtures/scenes")).unwrap() {
                let path = entry.unwrap().path();
                if path.extension().is_some_and(|e| e == "toml") {
                    let stem = path.file_stem().unwrap().to_string_lossy().into_owned();
                    assert!(tested.contains(&stem.as_str()), "scene {stem} has no mesh test");
                }
            }
        }
    };
}

preset_tests! {
    tiny_meshes_are_watertight: "tiny";
    default_meshes_are_watertight: "default";
    layered_meshes_are_watertight: "layered";
    branchwork_meshes_are_watertight: "branchwork";
    looping_meshes_are_watertight: "looping";
    rectilinear_meshes_are_watertight: "rectilinear";
    superimposed_meshes_are_watertight: "superimposed";
    karstnsim_meshes_are_watertight: "karstnsim";
    karstnsim_2phase_meshes_are_watertight: "karstnsim-2phase";
    waterfall_meshes_are_watertight: "waterfall";
    // In Lambert-93 (y ≈ 6.86e6, where an f32 steps by 0.5 m): watertight because the scene
    // is meshed in its local frame (issue 16).
    geotiff_meshes_are_watertight: "geotiff";
}
