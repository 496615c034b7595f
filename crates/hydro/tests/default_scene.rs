//! The default scene through the hydro stage: its shafts with water fall freely, every vadose
//! segment has a water type, the CSV tables and the water-type picture are written, and the
//! catchment recharge works on its terrain.

use std::path::Path;

use karst_artifact::read_artifact;
use karst_hydro::stage::{RenderArgs, render};
use karst_hydro::{Hydro, WaterType};
use karst_skeleton::{ConduitType, Skeleton, Zone};
use karst_testkit::{root, scratch};

fn run_to_hydro(scene: &Path, out: &Path) -> (Skeleton, Hydro) {
    std::fs::create_dir_all(out).unwrap();
    let args = (scene.to_path_buf(), out.to_path_buf());
    karst_testkit::run::<karst_sampling::SamplingStage>(&args.0, &args.1).unwrap();
    karst_testkit::run::<karst_costgraph::CostgraphStage>(&args.0, &args.1).unwrap();
    karst_testkit::run::<karst_skeleton::SkeletonStage>(&args.0, &args.1).unwrap();
    karst_testkit::run::<karst_hydro::HydroStage>(&args.0, &args.1).unwrap();
    let (_, skeleton) = read_artifact::<Skeleton>(&out.join("skeleton.json")).unwrap();
    let (_, hydro) = read_artifact::<Hydro>(&out.join("hydro.json")).unwrap();
    (skeleton, hydro)
}

#[test]
fn default_scene_shafts_with_water_are_free_falls() {
    let out = scratch("hydro-default");
    let (skeleton, hydro) = run_to_hydro(&root().join("fixtures/scenes/default.toml"), &out);
    let mut shafts = Vec::new();
    for (c, w) in skeleton.conduits.iter().zip(&hydro.conduits) {
        for ((pair, kind), seg) in c.nodes.windows(2).zip(&c.types).zip(&w.segments) {
            let vadose = pair.iter().all(|&n| skeleton.nodes[n as usize].zone == Zone::Vadose);
            if vadose && seg.flow > 0.0 {
                assert!(seg.water != WaterType::Dry && seg.water != WaterType::Sump);
            }
            if matches!(kind, ConduitType::Epikarst | ConduitType::Tube) && seg.flow > 0.0 && vadose {
                shafts.push(seg);
            }
        }
    }
    // Water rising up a shaft or leaving a filled low point ponds whatever the slope (as in the
    // loop below): the steepest shaft that runs must fall freely.
    let steepest = shafts
        .iter()
        .filter(|s| s.water != WaterType::Pool)
        .max_by(|a, b| a.slope.total_cmp(&b.slope))
        .expect("a shaft with running water");
    assert!(steepest.water.is_free_fall(), "{:?} at {} rad", steepest.water, steepest.slope);
    assert!(steepest.fall.as_ref().is_some_and(|f| f.drop > 0.0));
    for s in
        shafts.iter().filter(|s| s.slope > 3.0 * std::f64::consts::FRAC_PI_8 && s.water != WaterType::Pool)
    {
        assert!(s.water.is_free_fall(), "{:?} at {} rad", s.water, s.slope);
    }
    assert!(out.join("hydro_nodes.csv").exists() && out.join("hydro_links.csv").exists());
    render(&RenderArgs { dir: out.to_path_buf(), png: None }).unwrap();
    let png = std::fs::read(out.join("hydro.png")).unwrap();
    assert_eq!(&png[1..4], b"PNG");

    // The same network fed by the sinks' catchments on the terrain: water is still conserved.
    // The copy lives elsewhere: its data files are named by absolute path.
    let scenes = root().join("fixtures/scenes");
    let text = std::fs::read_to_string(scenes.join("default.toml"))
        .unwrap()
        .replace("file = \"data/", &format!("file = \"{}/data/", scenes.display()));
    let scene = out.join("catchment.toml");
    std::fs::write(&scene, format!("{text}\n[hydro]\nrecharge = \"catchment\"\n")).unwrap();
    karst_testkit::run::<karst_hydro::HydroStage>(&scene, &out).unwrap();
    let (_, hydro) = read_artifact::<Hydro>(&out.join("hydro.json")).unwrap();
    assert!(hydro.sinks.iter().all(|s| s.recharge > 0.0));
    let total: f64 = hydro.sinks.iter().map(|s| s.recharge).sum();
    let spring: f64 = hydro.springs.iter().map(|s| s.flow).sum();
    assert!((total - spring).abs() <= 1e-9 * total);
}
