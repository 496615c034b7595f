//! Issue 3's acceptance tests: surface samples lie on their surface, the spacing honours the
//! recorded radius field everywhere, and no sample lies in a no-karst volume or above the
//! terrain.

use glam::DVec3;
use karst_sampling::SamplingView;
use karst_sampling::build as sample_scene;
use karst_sampling::{Samples, Tag};
use karst_scene::Scene;
use karst_scene::SceneView;
use karst_testkit::root;

fn scene(file: &str) -> Scene {
    Scene::load(&root().join(file)).unwrap()
}

/// Every pair of samples (not both key points) closer than min(r(p), r(q)), found with a
/// uniform grid of cell max r.
fn spacing_violations(s: &Samples) -> Vec<(usize, usize, f64, f64)> {
    let f = &s.radius_field;
    let points: Vec<DVec3> = s.positions.iter().map(|p| DVec3::from_array(*p)).collect();
    let cell = f.max();
    let key = |p: DVec3| ((p / cell).floor()).as_ivec3();
    let mut grid: std::collections::BTreeMap<[i32; 3], Vec<usize>> = Default::default();
    for (i, p) in points.iter().enumerate() {
        grid.entry(key(*p).to_array()).or_default().push(i);
    }
    let mut bad = Vec::new();
    for (i, p) in points.iter().enumerate() {
        let c = key(*p);
        for dz in -1..=1 {
            for dy in -1..=1 {
                for dx in -1..=1 {
                    let Some(list) = grid.get(&(c + glam::IVec3::new(dx, dy, dz)).to_array()) else {
                        continue;
                    };
                    for &j in list.iter().filter(|&&j| j < i) {
                        let both_key =
                            matches!(s.tags[i], Tag::KeyPoint(_)) && matches!(s.tags[j], Tag::KeyPoint(_));
                        let m = f.at(*p).min(f.at(points[j]));
                        let d = p.distance(points[j]);
                        if !both_key && d < m * (1.0 - 1e-9) {
                            bad.push((i, j, d, m));
                        }
                    }
                }
            }
        }
    }
    bad
}

#[test]
fn default_scene_horizon_samples_lie_on_the_tsurf_horizon() {
    let scene = scene("fixtures/scenes/default.toml");
    assert!(matches!(scene.terrain(), karst_geology::Terrain::Heightfield { .. }));
    let horizon = &scene.geology().horizons[0];
    assert!(horizon.mesh().is_some(), "the default horizon is a TSurf");
    let s = sample_scene(&SamplingView::of(&scene)).unwrap();
    let on: Vec<DVec3> = s
        .positions
        .iter()
        .zip(&s.tags)
        .filter(|(_, t)| **t == Tag::Horizon(0))
        .map(|(p, _)| DVec3::from_array(*p))
        .collect();
    assert!(on.len() > 1000, "{} horizon samples", on.len());
    let close = on.iter().filter(|p| horizon.distance(**p) <= 0.01).count();
    assert!(close * 100 >= 95 * on.len(), "{close} of {} within 1 cm", on.len());
    let wt = &scene.geology().water_tables[0];
    let mut tagged = s.positions.iter().zip(&s.tags).filter(|(_, t)| **t == Tag::WaterTable(0));
    assert!(tagged.clone().count() > 1000);
    assert!(tagged.all(|(p, _)| wt.distance(DVec3::from_array(*p)) <= 0.01));
    assert!(spacing_violations(&s).is_empty());
}

#[test]
fn spacing_honours_the_variable_radius_field_everywhere() {
    let scene = scene("fixtures/scenes/layered.toml");
    let s = sample_scene(&SamplingView::of(&scene)).unwrap();
    let f = &s.radius_field;
    assert!(f.max() > 1.5 * f.min(), "the field varies: {} to {}", f.min(), f.max());
    let bad = spacing_violations(&s);
    assert!(bad.is_empty(), "{} pairs too close, first {:?}", bad.len(), bad.first());
    // Key points come first, exactly.
    for (i, k) in scene.keypoints().iter().enumerate() {
        assert_eq!(s.positions[s.keypoint_sample(i).unwrap()], k.position);
    }
    let again = sample_scene(&SamplingView::of(&scene)).unwrap();
    assert_eq!(s, again, "deterministic");
}

#[test]
fn no_sample_in_a_no_karst_volume_or_above_the_terrain() {
    let scene = scene("fixtures/scenes/layered.toml");
    assert!(!scene.geology().no_karst.is_empty());
    let s = sample_scene(&SamplingView::of(&scene)).unwrap();
    let c = s.tag_counts();
    assert!(c.volume > 1000 && c.horizon > 50 && c.fault > 20, "{c:?}");
    for p in &s.positions {
        let p = DVec3::from_array(*p);
        assert!(!scene.geology().in_no_karst(p), "{p} in a no-karst volume");
        assert!(p.z <= scene.terrain().height(p.x, p.y), "{p} above the terrain");
        assert!(scene.domain().contains(p));
    }
    // The no-karst volumes are not simply outside the sampled region: samples surround them.
    let near = s.positions.iter().filter(|p| {
        let q = DVec3::from_array(**p);
        scene.geology().no_karst.iter().any(|v| v.shape().unwrap().signed_distance(q, scene.geology()) < 15.0)
    });
    assert!(near.count() > 10);
}

#[test]
fn the_same_samples_whatever_the_thread_count() {
    let scene = scene("fixtures/scenes/layered.toml");
    let with = |threads: usize| {
        let pool = rayon::ThreadPoolBuilder::new().num_threads(threads).build().unwrap();
        pool.install(|| sample_scene(&SamplingView::of(&scene)).unwrap())
    };
    let one = with(1);
    assert_eq!(one, with(2));
    assert_eq!(one, with(3));
}

#[test]
fn the_volume_is_filled_up_to_small_holes() {
    // Constant radius (no surfaces): a point of the bedrock farther than r from every sample
    // could still take one. The saturation pass leaves only a small volume of such holes.
    let mut scene = scene("fixtures/scenes/tiny.toml");
    scene.geology_mut().water_tables.clear();
    scene.geology_mut().horizons.clear();
    scene.geology_mut().faults.clear();
    scene.geology_mut().layers.clear();
    scene.geology_mut().potential.clear();
    scene.keypoints_mut().retain(|k| k.water_table.is_none());
    let s = sample_scene(&SamplingView::of(&scene)).unwrap();
    let r = s.radius;
    let points: Vec<DVec3> = s.positions.iter().map(|p| DVec3::from_array(*p)).collect();
    let (lo, hi) = (scene.domain().min(), scene.domain().max());
    let mut rng = karst_scene::rng::Random::stream(3, "test", "holes");
    let (mut inside, mut holes) = (0, 0);
    for _ in 0..4000 {
        let p = DVec3::new(rng.range(lo.x, hi.x), rng.range(lo.y, hi.y), rng.range(lo.z, hi.z));
        if p.z >= scene.terrain().height(p.x, p.y) || scene.geology().in_no_karst(p) {
            continue;
        }
        inside += 1;
        if points.iter().all(|q| q.distance(p) >= r) {
            holes += 1;
        }
    }
    assert!(inside > 1000);
    eprintln!("{holes} holes in {inside} probes, {} samples", s.len());
    assert!(holes * 100 < inside, "{holes} holes in {inside} probes");
}

#[test]
fn tsurf_horizon_samples_lie_on_it_and_cover_it() {
    // Paths can run along a TSurf horizon only if its samples are on it and leave no gap on it
    // where another sample would fit.
    let scene = scene("fixtures/scenes/default.toml");
    let horizon = &scene.geology().horizons[0];
    let mesh = horizon.mesh().expect("the default horizon is a TSurf");
    let s = sample_scene(&SamplingView::of(&scene)).unwrap();
    let f = &s.radius_field;
    let points: Vec<DVec3> = s.positions.iter().map(|p| DVec3::from_array(*p)).collect();
    for (p, t) in points.iter().zip(&s.tags) {
        if *t == Tag::Horizon(0) {
            assert!(horizon.distance(*p) < 1e-6, "{p} is {} m off the horizon", horizon.distance(*p));
        }
    }
    // Uniform probes on the triangles, area-weighted, inside the sampled region.
    let areas: Vec<f64> = (0..mesh.triangles.len())
        .map(|t| {
            let [a, b, c] = mesh.triangle(t);
            0.5 * (b - a).cross(c - a).length()
        })
        .collect();
    let total: f64 = areas.iter().sum();
    let mut rng = karst_scene::rng::Random::stream(4, "test", "tin probes");
    let (mut inside, mut holes) = (0, 0);
    while inside < 1500 {
        let mut pick = rng.uniform() * total;
        let t = areas.iter().position(|a| {
            pick -= a;
            pick < 0.0
        });
        let [a, b, c] = mesh.triangle(t.unwrap_or(areas.len() - 1));
        let (u, v) = (rng.uniform().sqrt(), rng.uniform());
        let p = a * (1.0 - u) + b * (u * (1.0 - v)) + c * (u * v);
        let d = scene.domain();
        if !d.contains(p) || p.z >= scene.terrain().height(p.x, p.y) || scene.geology().in_no_karst(p) {
            continue;
        }
        inside += 1;
        // The horizon is filled after the key points and the water tables, before the volume.
        let r = f.at(p);
        let earlier = points
            .iter()
            .zip(&s.tags)
            .filter(|(_, t)| matches!(t, Tag::KeyPoint(_) | Tag::WaterTable(_) | Tag::Horizon(0)));
        if earlier.map(|(q, _)| q).all(|q| q.distance(p) >= r.min(f.at(*q))) {
            holes += 1;
        }
    }
    eprintln!("{holes} holes in {inside} probes on the TSurf horizon");
    assert!(holes * 50 < inside, "{holes} holes in {inside} probes on the TSurf horizon");
}
