//! The waterfall preset end to end through the stages: upstream stages, the streams, the sdf
//! model with its riverbeds, basins, overhangs and surface water, and the mesher. The carved
//! terrain, the cave (joined to the springs' mouths) and the water (underground and on the
//! surface: rivers, pools and falling sheets) are each closed 2-manifolds, and the carving is
//! where the streams say.

use glam::DVec3;
use karst_artifact::read_artifact;
use karst_mesher::{anchors, mesh_with, watertight};
use karst_scene::Scene;
use karst_sdf::{CarvedTerrain, SdfModel};
use karst_streams::{Outline, Streams};
use karst_testkit::{fixture, run, scratch};

#[test]
fn the_waterfall_preset_meshes_watertight_with_its_streams_carved() {
    let scene_path = fixture("fixtures/scenes/waterfall.toml");
    let out = scratch("waterfall");
    run::<karst_sampling::SamplingStage>(&scene_path, &out).unwrap();
    run::<karst_costgraph::CostgraphStage>(&scene_path, &out).unwrap();
    run::<karst_skeleton::SkeletonStage>(&scene_path, &out).unwrap();
    run::<karst_hydro::HydroStage>(&scene_path, &out).unwrap();
    run::<karst_streams::StreamsStage>(&scene_path, &out).unwrap();
    run::<karst_sdf::SdfStage>(&scene_path, &out).unwrap();
    let scene = Scene::load(&scene_path).unwrap();
    let (_, streams): (_, Streams) = read_artifact(&out.join("streams.json")).unwrap();
    let (_, model): (_, SdfModel) = read_artifact(&out.join("sdf.bin")).unwrap();
    std::fs::remove_dir_all(&out).unwrap();
    let field = CarvedTerrain::new(model);
    let mesh = mesh_with(&field, 1.0, 0.5, &anchors(scene.keypoints()));
    for (name, surface) in mesh.surfaces() {
        assert!(!surface.triangles.is_empty(), "{name} is empty");
        watertight::check(surface).unwrap_or_else(|e| panic!("{name}: {e:?}"));
    }
    // The carving is in the mesh: the water reaches down into the plunge pools, below the
    // terrain's own surface, and the falls' sheets hang in the air.
    let pool = streams.pools.iter().find(|p| p.fall.is_some()).unwrap();
    let Outline::Disc { centre, .. } = pool.outline else { panic!("a plunge pool is a disc") };
    let under = DVec3::new(centre[0], centre[1], pool.level - 0.5 * pool.depth);
    assert!(under.z < scene.terrain().height(under.x, under.y), "the basin is below the ground");
    assert!(field.eval(under) > 0.0 && field.water(under) < 0.0, "the basin is dug and full");
    let fall = streams.segments.iter().find_map(|s| s.fall.as_ref()).unwrap();
    let mid = DVec3::from_array(fall.at(0.5 * fall.throw));
    assert!(field.water(mid) < 0.0 && field.eval(mid) > 0.0, "a sheet of water in the air at {mid}");
    // Each spring's conduit opens onto its stream: the cave reaches the mouth.
    for s in &streams.springs {
        let mouth = DVec3::from_array(s.mouth.unwrap());
        assert!(field.cave(mouth) < 0.0, "{}: the cave reaches its mouth", s.name);
    }
}
