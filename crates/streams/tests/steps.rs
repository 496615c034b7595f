//! Every traced step goes down (Emilien et al. 2015 §5, Fig. 5): a contact step drops at least
//! `min_slope` times its horizontal length, a free fall leaves its lip horizontally or downwards
//! and lands lower, and the water crossing a pool leaves it lower than its level. Checked on
//! noise terrains (several patches of the noise, springs placed by a seeded generator), on
//! every preset's terrain with extra springs spread over it, and on a hand-built terrain with a
//! flat and a pit.

use karst_scene::SceneView;
use karst_streams::StreamsView;
use std::path::Path;

use glam::DVec3;
use karst_geology::heightfield::{HeightGrid, write_png};
use karst_hydro::{FlowUnits, Hydro, Spring};
use karst_scene::{KeyPoint, KeyPointKind, Scene};
use karst_streams::{Motion, Role, Streams, build};
use karst_testkit::{root, scratch};

/// The deepest a stream may run under the ground, metres: the tracer cuts at most a step's
/// worth of fall into a rise (2 m at the default step) before it treats it as a hollow.
const MAX_CUT: f64 = 2.5;

/// A hydro artifact giving every spring of `scene` the same flow.
fn hydro_of(scene: &Scene) -> Hydro {
    Hydro {
        flow_units: FlowUnits { min: 1.0, max: 1.0 },
        conduits: Vec::new(),
        nodes: Vec::new(),
        sinks: Vec::new(),
        springs: karst_scene::keypoints_of(scene.keypoints(), KeyPointKind::Spring)
            .map(|(_, k)| Spring { name: k.name.clone(), node: 0, flow: 1.0, sinks: Vec::new() })
            .collect(),
    }
}

/// The steps of `s` that do not go down as they must, described.
fn wrong_steps(s: &Streams, min_slope: f64) -> Vec<String> {
    let mut wrong = Vec::new();
    for (i, g) in s.segments.iter().enumerate() {
        let [a, b] = [g.from, g.to].map(|n| DVec3::from_array(s.nodes[n as usize].position));
        let run = a.truncate().distance(b.truncate());
        let drop = a.z - b.z;
        let ok = match g.motion {
            Motion::Contact | Motion::Pool => drop >= min_slope * run - 1e-9,
            Motion::FreeFall => drop > 0.0 && g.fall.as_ref().is_some_and(|f| f.vertical <= 0.0),
        };
        if !ok {
            wrong.push(format!("segment {i} ({:?}): {a} → {b}, drop {drop:.3} m over {run:.3} m", g.motion));
        }
    }
    wrong
}

/// The water goes down everywhere, runs in no circle (no trajectory stops at
/// `streams.max_length`) and cuts its bed at most `MAX_CUT` metres into the ground.
fn assert_downhill(s: &Streams, scene: &Scene, what: &str) {
    let wrong = wrong_steps(s, scene.streams().min_slope);
    assert!(
        wrong.is_empty(),
        "{what}: {} of {} steps do not go down:\n{}",
        wrong.len(),
        s.segments.len(),
        wrong.join("\n")
    );
    let circling: Vec<&String> = s.reports.iter().filter(|r| r.contains("max_length")).collect();
    assert!(circling.is_empty(), "{what}: {circling:?}");
    for g in s.segments.iter().filter(|g| g.motion == Motion::Contact) {
        let p = s.nodes[g.to as usize].position;
        let cut = scene.terrain().height(p[0], p[1]) - p[2];
        assert!(cut <= MAX_CUT, "{what}: the water at {p:?} runs {cut:.2} m under the ground");
    }
}

/// A spring deep down that scenes need to parse; [`add_springs`] brings it under the ground.
fn placeholder(x: f64, y: f64) -> String {
    format!(
        "[[keypoints]]\nname = \"placeholder\"\nkind = \"spring\"\nposition = [{x}, {y}, -100]\nwater_table = \"wt\"\n"
    )
}

/// Springs `depth` metres under the ground at `points`, and the placeholder spring moved there
/// too (at the first point).
fn add_springs(scene: &mut Scene, points: impl IntoIterator<Item = [f64; 2]>, depth: f64) {
    let water_table = scene.geology().water_tables.first().map(|w| w.name.clone());
    let new: Vec<KeyPoint> = points
        .into_iter()
        .enumerate()
        .map(|(i, [x, y])| KeyPoint {
            name: format!("extra-{i}"),
            kind: KeyPointKind::Spring,
            position: [x, y, scene.terrain().height(x, y) - depth],
            weight: 1.0,
            order: 0,
            water_table: water_table.clone(),
        })
        .collect();
    let [x, y, _] = new[0].position;
    let z = scene.terrain().height(x, y + 1.0) - depth;
    if let Some(k) = scene.keypoints_mut().iter_mut().find(|k| k.name == "placeholder") {
        k.position = [x, y + 1.0, z];
    }
    scene.keypoints_mut().extend(new);
}

/// A small portable generator for the springs' positions.
struct Lcg(u64);

impl Lcg {
    fn unit(&mut self) -> f64 {
        self.0 = self.0.wrapping_mul(6_364_136_223_846_793_005).wrapping_add(1_442_695_040_888_963_407);
        (self.0 >> 11) as f64 / (1u64 << 53) as f64
    }
}

/// A scene in `dir` over the heightfield `height` sampled every `cell` metres on [0, size],
/// with the placeholder spring and `rest` appended.
fn heightfield_scene(
    dir: &Path,
    cell: f64,
    size: [f64; 2],
    height: impl Fn(f64, f64) -> f64,
    rest: &str,
) -> Scene {
    let [nx, ny] = size.map(|s| (s / cell).round() as usize + 1);
    let heights = (0..ny)
        .flat_map(|j| (0..nx).map(move |i| (i, j)))
        .map(|(i, j)| height(cell * i as f64, cell * j as f64));
    write_png(
        &dir.join("terrain.png"),
        &HeightGrid::new([0.0, 0.0], cell, nx as u32, ny as u32, heights.collect()),
        0.0,
        0.01,
    )
    .unwrap();
    let text = format!(
        "name = \"hand-built\"\nseed = 1\n[domain]\nmin = [0, 0, -200]\nmax = [{}, {}, 120]\n\
         [terrain]\nkind = \"heightfield\"\nfile = \"terrain.png\"\ncell_size = {cell}\norigin = [0, 0]\n\
         vertical_scale = 0.01\n\
         [[geology.water_tables]]\nname = \"wt\"\nelevation = 10\n\
         [[keypoints]]\nname = \"a\"\nkind = \"sink\"\nposition = [10, 10, 20]\n{}{rest}",
        size[0],
        size[1],
        placeholder(20.0, 20.0)
    );
    Scene::parse(&text, &dir.join("scene.toml")).unwrap_or_else(|e| panic!("{e}"))
}

#[test]
fn every_step_goes_down_on_noise_terrains() {
    let dir = scratch("steps-noise");
    for seed in 0..8u64 {
        let mut rng = Lcg(seed + 1);
        // A domain elsewhere per seed (the scene is localized at its corner, where the noise is
        // anchored), with its own roughness and tilt; the springs go in local coordinates.
        let (x0, y0) = (1000.0 * seed as f64, 700.0 * seed as f64);
        let amplitude = 3.0 + 6.0 * rng.unit();
        let wavelength = 40.0 + 60.0 * rng.unit();
        let tilt = [-0.05 - 0.15 * rng.unit(), 0.1 * (rng.unit() - 0.5)];
        let text = format!(
            "name = \"n{seed}\"\nseed = {seed}\n[domain]\nmin = [{x0}, {y0}, -200]\nmax = [{}, {}, 200]\n\
             [terrain]\nkind = \"noise\"\nelevation = {}\namplitude = {amplitude}\nwavelength = {wavelength}\n\
             gradient = [{}, {}]\n\
             [[geology.water_tables]]\nname = \"wt\"\nelevation = 10\n\
             [[keypoints]]\nname = \"a\"\nkind = \"sink\"\nposition = [{}, {}, -100]\n\
             {}[streams]\nrunoff = 2000\n",
            x0 + 300.0,
            y0 + 200.0,
            60.0,
            tilt[0],
            tilt[1],
            x0 + 10.0,
            y0 + 10.0,
            placeholder(x0 + 20.0, y0 + 20.0),
        );
        let mut scene = Scene::parse(&text, &dir.join("n.toml")).unwrap_or_else(|e| panic!("{e}"));
        let points: Vec<[f64; 2]> =
            (0..12).map(|_| [10.0 + 280.0 * rng.unit(), 10.0 + 180.0 * rng.unit()]).collect();
        add_springs(&mut scene, points, 1.0 + 4.0 * rng.unit());
        let streams = build(&StreamsView::of(&scene), &hydro_of(&scene)).unwrap();
        assert!(streams.segments.len() > 100, "seed {seed}: {} segments", streams.segments.len());
        assert_downhill(&streams, &scene, &format!("noise seed {seed}"));
    }
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn every_step_goes_down_on_the_presets_terrains() {
    let mut presets: Vec<_> = std::fs::read_dir(root().join("fixtures/scenes"))
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|e| e == "toml"))
        .collect();
    presets.sort();
    assert!(presets.len() >= 9, "{presets:?}");
    for path in presets {
        let mut scene = Scene::load(&path).unwrap_or_else(|e| panic!("{e}"));
        // The preset's own springs, and a 6 × 5 lattice of springs over its footprint.
        let (lo, hi) = (scene.domain().min, scene.domain().max);
        let points: Vec<[f64; 2]> = (0..30)
            .map(|k| {
                let (i, j) = ((k % 6) as f64 + 0.5, (k / 6) as f64 + 0.5);
                [lo[0] + (hi[0] - lo[0]) * i / 6.0, lo[1] + (hi[1] - lo[1]) * j / 5.0]
            })
            .collect();
        add_springs(&mut scene, points, 0.5);
        let streams = build(&StreamsView::of(&scene), &hydro_of(&scene)).unwrap();
        assert_downhill(&streams, &scene, &path.display().to_string());
    }
}

#[test]
fn every_step_goes_down_over_a_flat_and_a_pit() {
    let dir = scratch("steps-flat-pit");
    // A valley falling east at 10 %, its floor flat across (12 m wide, sides rising at 20 %),
    // a flat terrace at 50 m from x = 60 to 100, a pit 4 m deep and 16 m across on the floor
    // below it, the valley on to the domain's edge.
    let height = |x: f64, y: f64| {
        let slope = if x < 60.0 {
            56.0 - 0.1 * x
        } else if x < 100.0 {
            50.0
        } else {
            50.0 - 0.1 * (x - 100.0)
        };
        let r = ((x - 130.0).powi(2) + (y - 60.0).powi(2)).sqrt();
        let side = 0.2 * ((y - 60.0).abs() - 6.0).max(0.0);
        slope + side - 4.0 * (1.0 - (r / 8.0).powi(2)).max(0.0)
    };
    let mut scene = heightfield_scene(&dir, 2.0, [200.0, 120.0], height, "[streams]\ncatchment_cell = 2\n");
    add_springs(&mut scene, (0..5).map(|k| [10.0, 50.0 + 5.0 * k as f64]), 0.5);
    let streams = build(&StreamsView::of(&scene), &hydro_of(&scene)).unwrap();
    // The streams cross the flat and fill the pit to its lowest rim (46.2 m, downstream)
    // before they leave by the east side.
    assert_eq!(streams.pools.len(), 1, "{:?}", streams.pools);
    // Stream elevations are local: the domain's floor (−200 m) is their zero.
    let level = streams.pools[0].level + scene.origin()[2];
    assert!((level - 46.2).abs() < 0.5, "the pit fills to {level}");
    assert!(
        streams.nodes.iter().any(|n| n.role == Role::Well && n.position[0] > 199.0 && n.inflow > 0.99),
        "the water leaves by the east side"
    );
    assert!(
        streams.segments.iter().any(|g| {
            let p = streams.nodes[g.to as usize].position;
            p[0] > 70.0 && p[0] < 90.0
        }),
        "a stream crosses the flat"
    );
    assert_downhill(&streams, &scene, "flat and pit");
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn a_step_over_a_lip_is_refined_onto_the_terrain() {
    let dir = scratch("steps-lip");
    // A valley falling east at 10 %, a knick at x = 100 where the floor drops 1.5 m over half a
    // metre: too short a drop for the slow water to fly a step, so it runs over the lip.
    let height = |x: f64, y: f64| {
        let knick = 3.0 * (x - 100.0).clamp(0.0, 0.5);
        60.0 - 0.1 * x - knick + 0.2 * ((y - 30.0).abs() - 4.0).max(0.0)
    };
    let mut scene = heightfield_scene(&dir, 0.5, [200.0, 60.0], height, "");
    add_springs(&mut scene, [[60.0, 30.0]], 0.5);
    let streams = build(&StreamsView::of(&scene), &hydro_of(&scene)).unwrap();
    assert_downhill(&streams, &scene, "lip");
    assert!(
        streams.segments.iter().all(|g| g.motion == Motion::Contact),
        "the water does not fly off the lip"
    );
    // Every step near the lip has its midpoint on the terrain (as deep under it as its ends),
    // to within what three halvings of a 2 m step leave at a 75° knick.
    let ground = |p: DVec3| scene.terrain().height(p.x, p.y);
    let mut near = 0;
    for g in &streams.segments {
        let [a, b] = [g.from, g.to].map(|n| DVec3::from_array(streams.nodes[n as usize].position));
        let m = 0.5 * (a + b);
        if (m.x - 100.25).abs() > 3.0 {
            continue;
        }
        near += 1;
        let off = ground(m) - 0.5 * ((ground(a) - a.z) + (ground(b) - b.z)) - m.z;
        assert!(off.abs() <= 0.25, "{a} → {b}: the midpoint lies {off:.2} m off the terrain");
    }
    assert!(near >= 3, "{near} steps near the lip");
    let _ = std::fs::remove_dir_all(&dir);
}
