//! Whole construction trees: the tiny scene's network (its golden skeleton, flows and streams),
//! every other preset of fixtures/scenes (run through the upstream stages, their surface
//! streams carved in) and a synthetic network of a few thousand primitives. On each, the field,
//! the karst volume and the water are 1-Lipschitz on random pairs, most of them near the
//! leaves (and the riverbeds, basins, alcoves and sheets) where the field is intricate; the
//! BVH's pruning changes nothing and the sign agrees with a brute-force inside test over every
//! leaf.

use karst_scene::SceneView;
use karst_sdf::SdfView;
use std::path::Path;

use glam::DVec3;
use karst_artifact::read_artifact;
use karst_hydro::Hydro;
use karst_scene::Scene;
use karst_sdf::{CarvedTerrain, add_streams, build, synthetic};
use karst_skeleton::Skeleton;
use karst_streams::Streams;
use karst_testkit::{root, scratch};

/// The tree of `scene` from the skeleton, hydro and streams artifacts in `dir`, as the sdf
/// stage builds it.
fn field_of(scene: &Path, dir: &Path) -> CarvedTerrain {
    let scene = Scene::load(scene).unwrap();
    let (_, skeleton): (_, Skeleton) = read_artifact(&dir.join("skeleton.json")).unwrap();
    let (_, hydro): (_, Hydro) = read_artifact(&dir.join("hydro.json")).unwrap();
    let (_, streams): (_, Streams) = read_artifact(&dir.join("streams.json")).unwrap();
    let mut model = build(&SdfView::of(&scene), &skeleton, &hydro).unwrap();
    add_streams(&mut model, &streams, scene.streams());
    CarvedTerrain::new(model)
}

fn synthetic_field(conduits: usize) -> CarvedTerrain {
    synthetic_field_in(&synthetic_scene(), conduits)
}

fn synthetic_field_in(scene: &karst_scene::Scene, conduits: usize) -> CarvedTerrain {
    let (skeleton, hydro) = synthetic::network(5, conduits, 12);
    CarvedTerrain::new(build(&SdfView::of(scene), &skeleton, &hydro).unwrap())
}

/// A small deterministic generator.
struct Lcg(u64);

impl Lcg {
    fn unit(&mut self) -> f64 {
        self.0 = self.0.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
        (self.0 >> 11) as f64 / (1u64 << 53) as f64
    }

    fn offset(&mut self, reach: f64) -> DVec3 {
        DVec3::new(self.unit() - 0.5, self.unit() - 0.5, self.unit() - 0.5) * 2.0 * reach
    }
}

/// Points near the leaves (where the field is intricate) and anywhere in the domain.
fn points(field: &CarvedTerrain, n: usize, seed: u64) -> Vec<DVec3> {
    let model = field.model();
    let v = |a: [f32; 3]| DVec3::new(a[0] as f64, a[1] as f64, a[2] as f64);
    let anchors: Vec<DVec3> = model
        .sweeps
        .iter()
        .map(|s| v(s.sweep.a))
        .chain(model.spheres.iter().flat_map(|g| g.spheres.iter()).map(|s| v([s[0], s[1], s[2]])))
        .chain(model.chambers.iter().map(|c| v(c.a)))
        .chain(model.surface.beds.iter().map(|b| DVec3::from_array(b.a)))
        .chain(model.surface.alcoves.iter().map(|c| DVec3::from_array(c.a)))
        .chain(model.surface.sheets.iter().map(|s| DVec3::from_array(s.a)))
        .chain(model.full.pieces().iter().map(|p| p.centre()))
        .collect();
    let (lo, hi) = (DVec3::from_array(model.domain.min), DVec3::from_array(model.domain.max));
    let mut rng = Lcg(seed);
    (0..n)
        .map(|i| {
            if i % 4 == 3 || anchors.is_empty() {
                lo + (hi - lo) * DVec3::new(rng.unit(), rng.unit(), rng.unit())
            } else {
                anchors[(rng.unit() * anchors.len() as f64) as usize % anchors.len()] + rng.offset(6.0)
            }
        })
        .collect()
}

fn assert_lipschitz(name: &str, f: impl Fn(DVec3) -> f64, field: &CarvedTerrain, n: usize) {
    let mut rng = Lcg(99);
    for p in points(field, n, 17) {
        let reach = [0.05, 0.5, 3.0][(rng.unit() * 3.0) as usize % 3];
        let q = p + rng.offset(reach);
        let (fp, fq) = (f(p), f(q));
        assert!((fp - fq).abs() <= p.distance(q) * (1.0 + 1e-5), "{name}: f({p}) = {fp}, f({q}) = {fq}");
    }
}

fn check_tree(field: &CarvedTerrain, n: usize) {
    assert_lipschitz("eval", |p| field.eval(p), field, n);
    assert_lipschitz("cave", |p| field.cave(p), field, n);
    assert_lipschitz("water", |p| field.water(p), field, n);
    check_gathered(field, n / 20);
}

/// The leaf nodes the mesher gathers for a brick give, at every point of the brick, the same
/// bits as the hierarchy: boxes of 1–4 m around points near the leaves, 10 points each.
fn check_gathered(field: &CarvedTerrain, boxes: usize) {
    let mut rng = Lcg(5);
    for lo in points(field, boxes, 23) {
        let hi = lo + DVec3::splat(1.0 + 3.0 * rng.unit());
        let reach = 0.3 + 6.0 * rng.unit();
        let (near, near_cave) = (field.near(lo, hi, reach), field.near_cave(lo, hi, reach));
        let near_water = field.near_water(lo, hi, reach);
        for _ in 0..10 {
            let p = lo + (hi - lo) * DVec3::new(rng.unit(), rng.unit(), rng.unit());
            let r = reach * (0.5 + 0.5 * rng.unit());
            let at = format!("{p} reach {r}");
            assert_eq!(
                field.eval_near(&near, p, r).to_bits(),
                field.eval_within(p, r).to_bits(),
                "eval {at}"
            );
            let (cave, cave_near) =
                (field.cave_below_ground(p, r), field.cave_below_ground_near(&near_cave, p, r));
            assert_eq!(cave_near.to_bits(), cave.to_bits(), "cave {at}");
            assert_eq!(
                field.water_near(&near_water, p, r).to_bits(),
                field.water_within(p, r).to_bits(),
                "water {at}"
            );
        }
    }
}

#[test]
fn tiny_tree_is_one_lipschitz() {
    let field = field_of(&root().join("fixtures/scenes/tiny.toml"), &root().join("fixtures/golden/tiny"));
    assert!(!field.model().water.is_empty());
    check_tree(&field, 20_000);
    check_sign(&field, 1000, "tiny");
}

/// The tree of a preset scene, its upstream stages run into a scratch folder.
fn preset_field(name: &str) -> CarvedTerrain {
    let scene = root().join(format!("fixtures/scenes/{name}.toml"));
    let out = scratch(&format!("sdf-{name}"));
    stages_field(&scene, &out)
}

/// The tree of `scene`, its upstream stages run into `out`.
fn stages_field(scene: &Path, out: &Path) -> CarvedTerrain {
    karst_testkit::run::<karst_sampling::SamplingStage>(scene, out).unwrap();
    karst_testkit::run::<karst_costgraph::CostgraphStage>(scene, out).unwrap();
    karst_testkit::run::<karst_skeleton::SkeletonStage>(scene, out).unwrap();
    karst_testkit::run::<karst_hydro::HydroStage>(scene, out).unwrap();
    karst_testkit::run::<karst_streams::StreamsStage>(scene, out).unwrap();
    field_of(scene, out)
}

/// The tree of a preset scene with `[sdf] passage_detail = "full"`: the scene is copied into a
/// scratch folder with its data files named from the presets' folder.
fn detailed_preset_field(name: &str) -> CarvedTerrain {
    preset_field_at(name, "full")
}

/// The tree of a preset scene at passage detail `level`.
fn preset_field_at(name: &str, level: &str) -> CarvedTerrain {
    let scenes = root().join("fixtures/scenes");
    let text = std::fs::read_to_string(scenes.join(format!("{name}.toml"))).unwrap();
    assert!(!text.contains("\n[sdf]"), "{name} has an [sdf] section: add the level to it");
    let text = text.replace("file = \"data/", &format!("file = \"{}/data/", scenes.display()))
        + &format!("\n[sdf]\npassage_detail = \"{level}\"\n");
    let out = scratch(&format!("sdf-{name}-{level}"));
    let scene = out.join(format!("{name}.toml"));
    std::fs::write(&scene, text).unwrap();
    stages_field(&scene, &out)
}

/// On a preset's tree: 1-Lipschitz on pairs near its leaves (and a quarter anywhere); the BVH
/// changes nothing and the sign agrees with a brute-force inside test over every leaf.
fn check_preset(name: &str, pairs: usize, brute: usize) {
    let field = preset_field(name);
    assert!(field.leaves() > 0, "{name}: no leaves");
    check_tree(&field, pairs);
    check_sign(&field, brute, name);
}

/// The same with full passage detail: the runs of profile pieces (one leaf per segment), the
/// profiles' sphere stations, the rough walls' relief, the speleothems and breakdown blocks
/// keep the tree 1-Lipschitz (on pairs and by its gradient) and the BVH exact.
fn check_detailed_preset(name: &str, pairs: usize, brute: usize) {
    let field = detailed_preset_field(name);
    assert!(field.model().sweeps.iter().any(|s| s.continues), "{name}: no passage profile was swept");
    assert!(field.model().full.relief().is_some(), "{name}: no wall relief");
    check_tree(&field, pairs);
    check_gradient(&field, pairs / 4);
    check_sign(&field, brute, name);
}

/// The slope of the field (eval and cave) at points near the leaves and the rock pieces, along
/// its central-difference gradient: at most 1 up to the quotient's error, where the relief is
/// steepest.
fn check_gradient(field: &CarvedTerrain, n: usize) {
    let h = 1e-4;
    let mut steepest: f64 = 0.0;
    for p in points(field, n, 41) {
        for (name, f) in
            [("eval", &(|q| field.eval(q)) as &dyn Fn(DVec3) -> f64), ("cave", &|q| field.cave(q))]
        {
            let g = DVec3::new(
                f(p + DVec3::X * h) - f(p - DVec3::X * h),
                f(p + DVec3::Y * h) - f(p - DVec3::Y * h),
                f(p + DVec3::Z * h) - f(p - DVec3::Z * h),
            ) / (2.0 * h);
            // The slope along the estimated gradient's direction, one difference quotient: where
            // a min or a max switches between the axes' samples the three axes' differences come
            // from different pieces and their vector may exceed 1 (1.017 at a point of the
            // default scene whose every directional quotient is below 0.9999), while the slope
            // along one direction is a Lipschitz quotient itself.
            let u = g.normalize_or_zero();
            let slope = (f(p + u * h) - f(p - u * h)).abs() / (2.0 * h);
            assert!(slope <= 1.0 + 1e-3, "{name}: slope {slope} at {p} along {u} (|∇f| ≈ {})", g.length());
            steepest = steepest.max(slope);
        }
    }
    assert!(steepest > 0.5, "the estimates found no slope at all ({steepest})");
}

/// The default preset with full detail has speleothems, breakdown blocks and sediment fills in
/// its tree.
#[test]
fn default_tree_with_full_detail_has_speleothems_and_blocks() {
    use karst_sdf::detail::rock::PieceKind;
    let field = detailed_preset_field("default");
    let pieces = field.model().full.pieces();
    let count = |k: PieceKind| pieces.iter().filter(|p| p.kind == k).count();
    for kind in [
        PieceKind::Stalactite,
        PieceKind::Stalagmite,
        PieceKind::Flowstone,
        PieceKind::Block,
        PieceKind::Sediment,
    ] {
        assert!(count(kind) > 0, "no {}", kind.name());
    }
}

macro_rules! detailed_preset_tests {
    ($($test:ident: $name:literal, $pairs:literal, $brute:literal;)*) => {$(
        #[test]
        fn $test() {
            check_detailed_preset($name, $pairs, $brute);
        }
    )*};
}

detailed_preset_tests! {
    default_tree_with_passage_detail_is_one_lipschitz: "default", 10_000, 500;
    looping_tree_with_passage_detail_is_one_lipschitz: "looping", 5000, 100;
    karstnsim_tree_with_passage_detail_is_one_lipschitz: "karstnsim", 5000, 100;
    waterfall_tree_with_passage_detail_is_one_lipschitz: "waterfall", 5000, 100;
}

macro_rules! preset_tests {
    ($($test:ident: $name:literal, $pairs:literal, $brute:literal;)*) => {$(
        #[test]
        fn $test() {
            check_preset($name, $pairs, $brute);
        }
    )*};
}

preset_tests! {
    default_tree_is_one_lipschitz: "default", 10_000, 1000;
    branchwork_tree_is_one_lipschitz: "branchwork", 5000, 200;
    looping_tree_is_one_lipschitz: "looping", 5000, 100;
    rectilinear_tree_is_one_lipschitz: "rectilinear", 5000, 200;
    superimposed_tree_is_one_lipschitz: "superimposed", 5000, 200;
    karstnsim_tree_is_one_lipschitz: "karstnsim", 5000, 200;
    karstnsim_2phase_tree_is_one_lipschitz: "karstnsim-2phase", 5000, 200;
    layered_tree_is_one_lipschitz: "layered", 5000, 200;
    geotiff_tree_is_one_lipschitz: "geotiff", 5000, 200;
}

/// The waterfall preset with its streams carved in: riverbeds, an alcove behind each fall and
/// the falling sheets are in the tree; 1-Lipschitz on pairs around them (the preset test's
/// points include the surface pieces) and the gathered leaves agree with the hierarchy.
#[test]
fn waterfall_tree_with_its_streams_is_one_lipschitz() {
    let field = preset_field("waterfall");
    let surface = &field.model().surface;
    assert!(!surface.beds.is_empty() && !surface.alcoves.is_empty() && !surface.sheets.is_empty());
    check_tree(&field, 20_000);
    check_sign(&field, 200, "waterfall");
}

/// A pool controller (a flat closed curve with its own flow) is dug into a flat terrain: air
/// and water down to its floor, rock below it and outside its banks; 1-Lipschitz around it.
#[test]
fn a_pool_controller_is_dug_into_the_terrain() {
    let dir = karst_testkit::scratch("pool-curve");
    let text = karst_testkit::SceneText::new("pool")
        .with(
            "[[streams.curves]]\nname = \"tarn\"\nkind = \"pool\"\nflow = 0.2\ntension = 1\n\
             points = [[40, 40, 39.5], [60, 40, 39.5], [60, 60, 39.5], [40, 60, 39.5]]",
        )
        .text();
    let scene = Scene::parse(&text, &dir.join("pool.toml")).unwrap();
    let hydro = Hydro {
        flow_units: karst_hydro::FlowUnits { min: 1.0, max: 1.0 },
        conduits: Vec::new(),
        nodes: Vec::new(),
        sinks: Vec::new(),
        springs: Vec::new(),
    };
    let skeleton =
        Skeleton { nodes: Vec::new(), conduits: Vec::new(), routes: Vec::new(), derived: Default::default() };
    let streams = karst_streams::build(&karst_streams::StreamsView::of(&scene), &hydro).unwrap();
    let pool = streams.pools.iter().find(|p| p.kind == karst_streams::PoolKind::Curve).unwrap();
    let floor = pool.level - pool.depth;
    assert!(pool.depth > 2.0 && (pool.level - 39.5).abs() < 1e-9, "{pool:?}");
    let bare = CarvedTerrain::new(build(&SdfView::of(&scene), &skeleton, &hydro).unwrap());
    let mut model = build(&SdfView::of(&scene), &skeleton, &hydro).unwrap();
    add_streams(&mut model, &streams, scene.streams());
    assert_eq!(model.surface.basins.len(), 1);
    let field = CarvedTerrain::new(model);
    let centre = DVec3::new(50.0, 50.0, 0.5 * (pool.level + floor));
    assert!(bare.eval(centre) < 0.0, "rock before the pool is dug");
    assert!(field.eval(centre) > 0.0 && field.water(centre) < 0.0, "dug and full at {centre}");
    assert!(field.eval(centre.with_z(floor - 0.3)) < 0.0, "rock under the floor");
    assert!(
        field.eval(DVec3::new(50.0, 50.0, 39.8)) > 0.0 && field.water(DVec3::new(50.0, 50.0, 39.8)) > 0.0
    );
    assert!(field.eval(DVec3::new(20.0, 50.0, 39.5)) < 0.0, "rock beyond the banks");
    let mut rng = Lcg(7);
    for _ in 0..20_000 {
        let p = DVec3::new(30.0, 30.0, 35.0)
            + DVec3::new(rng.unit(), rng.unit(), rng.unit()) * DVec3::new(40.0, 40.0, 8.0);
        let reach = [0.05, 0.5, 3.0][(rng.unit() * 3.0) as usize % 3];
        let q = p + rng.offset(reach);
        for (what, f) in [("eval", field.eval(p) - field.eval(q)), ("water", field.water(p) - field.water(q))]
        {
            assert!(f.abs() <= p.distance(q) * (1.0 + 1e-5), "{what}: {p} {q}");
        }
    }
    std::fs::remove_dir_all(&dir).unwrap();
}

/// Every fixtures/scenes/*.toml preset has its test above.
#[test]
fn every_preset_is_tested() {
    let tested = [
        "tiny",
        "default",
        "branchwork",
        "looping",
        "rectilinear",
        "superimposed",
        "karstnsim",
        "karstnsim-2phase",
        "layered",
        "waterfall",
        "geotiff",
    ];
    for entry in std::fs::read_dir(root().join("fixtures/scenes")).unwrap() {
        let path = entry.unwrap().path();
        if path.extension().is_some_and(|e| e == "toml") {
            let stem = path.file_stem().unwrap().to_string_lossy().into_owned();
            assert!(tested.contains(&stem.as_str()), "preset {stem} has no tree test");
        }
    }
}

/// Both constructions: every conduit swept with mitred bends (the default), and the paper's
/// unions of spheres for the tortuous conduits (`passage_detail = "off"`).
#[test]
fn synthetic_tree_is_one_lipschitz() {
    let mitred = synthetic_field(160);
    assert!(mitred.model().spheres.is_empty(), "every conduit is swept");
    assert!(!mitred.model().chambers.is_empty() && mitred.leaves() > 500, "{} leaves", mitred.leaves());
    check_tree(&mitred, 20_000);
    let text = format!("{}\n[sdf]\npassage_detail = \"off\"\n", synthetic::SCENE);
    let off = karst_scene::Scene::parse(&text, std::path::Path::new("synthetic.toml")).unwrap();
    let spheres = synthetic_field_in(&off, 160);
    assert!(spheres.leaves() > 2000, "{} leaves", spheres.leaves());
    assert!(!spheres.model().spheres.is_empty() && !spheres.model().sweeps.is_empty());
    check_tree(&spheres, 20_000);
}

/// The BVH changes nothing, and the sign of f agrees with a brute-force inside test.
#[test]
fn sign_agrees_with_brute_force() {
    check_sign(&synthetic_field(40), 5000, "synthetic");
}

/// At `n` points near the leaves: the union through the BVH equals the union over every leaf,
/// and f is negative exactly in rock (below the terrain, inside the domain) outside the karst,
/// away from the entrance blend.
fn check_sign(field: &CarvedTerrain, n: usize, name: &str) {
    let model = field.model();
    for p in points(field, n, 3) {
        let cave = field.cave_without_bvh(p);
        assert_eq!(cave, field.cave(p), "{name}: the BVH changed the union at {p}");
        let rock = field.rock(p);
        let f = field.eval(p);
        // The entrance blend only acts where −rock and cave are within `blend` of each other.
        if (-rock - cave).abs() >= model.blend {
            assert_eq!(f < 0.0, rock < 0.0 && cave > 0.0, "{name} at {p}: f = {f}, rock {rock}, cave {cave}");
        }
    }
}

/// The scene of the synthetic network.
fn synthetic_scene() -> karst_scene::Scene {
    karst_scene::Scene::parse(synthetic::SCENE, std::path::Path::new("synthetic.toml")).unwrap()
}
