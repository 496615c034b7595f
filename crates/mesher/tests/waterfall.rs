//! The waterfall preset end to end, through the libraries: upstream stages, the streams,
//! the sdf model with its riverbeds, basins, overhangs and surface water, and the mesher. The
//! carved terrain, the cave (joined to the springs' mouths) and the water (underground and on
//! the surface: rivers, pools and falling sheets) are each closed 2-manifolds.

use std::path::Path;

use glam::DVec3;
use karst_artifact::cli::RunArgs;
use karst_artifact::read_artifact;
use karst_geology::Scene;
use karst_hydro::Hydro;
use karst_mesher::{build, stage, watertight};
use karst_sdf::CarvedTerrain;
use karst_skeleton::Skeleton;

#[test]
fn the_waterfall_preset_meshes_watertight_with_its_streams_carved() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("../..");
    let scene_path = root.join("fixtures/scenes/waterfall.toml");
    let out = std::env::temp_dir().join(format!("karst-mesher-waterfall-{}", std::process::id()));
    let args = RunArgs { scene: scene_path.clone(), out: out.clone() };
    karst_sampling::stage::run(&args).unwrap();
    karst_costgraph::stage::run(&args).unwrap();
    karst_skeleton::stage::run(&args).unwrap();
    karst_hydro::stage::run(&args).unwrap();
    let scene = Scene::load(&scene_path).unwrap();
    let (_, skeleton): (_, Skeleton) = read_artifact(&out.join("skeleton.json")).unwrap();
    let (_, hydro): (_, Hydro) = read_artifact(&out.join("hydro.json")).unwrap();
    let _ = std::fs::remove_dir_all(&out);
    let streams = karst_streams::build(&scene, &hydro).unwrap();
    let plain = karst_sdf::build::build(&scene, &skeleton, &hydro).unwrap();
    let mut model = plain.clone();
    karst_sdf::surface_water::add(&mut model, &streams, &scene.streams);
    let field = CarvedTerrain::new(model);
    let anchors = stage::anchors(&scene);
    let mesh = build::build_with(&field, 1.0, 0.5, &anchors);
    for (name, surface) in mesh.surfaces() {
        assert!(!surface.triangles.is_empty(), "{name} is empty");
        watertight::check(surface).unwrap_or_else(|e| panic!("{name}: {e:?}"));
    }
    // The carving is in the mesh: the water reaches down into the plunge pools, below the
    // terrain's own surface, and the falls' sheets hang in the air.
    let pool = streams.pools.iter().find(|p| p.fall.is_some()).unwrap();
    let karst_streams::Outline::Disc { centre, .. } = pool.outline else { panic!() };
    let under = DVec3::new(centre[0], centre[1], pool.level - 0.5 * pool.depth);
    assert!(field.eval(under) > 0.0 && field.water(under) < 0.0, "the basin is dug and full");
    let fall = streams.segments.iter().find_map(|s| s.fall.as_ref()).unwrap();
    let mid = DVec3::from_array(fall.at(0.5 * fall.throw));
    assert!(field.water(mid) < 0.0 && field.eval(mid) > 0.0, "a sheet of water in the air at {mid}");
    // Each spring's conduit opens onto its stream: the cave reaches the mouth.
    for s in &streams.springs {
        let mouth = DVec3::from_array(s.mouth.unwrap());
        assert!(field.cave(mouth) < 0.0, "{}: the cave reaches its mouth", s.name);
    }
    let evaluations = |s: &karst_mesher::Surface| s.field_evaluations as f64 / s.vertices.len().max(1) as f64;
    let uncarved = build::build_with(&CarvedTerrain::new(plain), 1.0, 0.5, &anchors);
    eprintln!(
        "waterfall: terrain {} triangles, {:.2} evaluations per vertex ({:.2} without the streams); water {} triangles",
        mesh.terrain.triangles.len(),
        evaluations(&mesh.terrain),
        evaluations(&uncarved.terrain),
        mesh.water.triangles.len()
    );
}
