//! The mesher's promises: closed, 2-manifold, consistently oriented surfaces without degenerate
//! triangles, the right areas and volumes, and the same bytes whatever the thread count.

use glam::DVec3;

use karst_geology::Domain;
use karst_mesher::mesh as mesh_field;
use karst_mesher::polygonize;
use karst_mesher::{Cave, Volume};
use karst_mesher::{Mesh, TriMesh, components, watertight};
use karst_mesher::{Solid, clean};
use karst_sdf::{Capsule, CarvedTerrain, SdfModel, TerrainField};

const PI: f64 = std::f64::consts::PI;

fn model() -> SdfModel {
    SdfModel {
        capsules: vec![
            Capsule { a: [10.0, 20.0, 28.0], b: [15.0, 20.0, 12.0], radius: 2.5 },
            Capsule { a: [15.0, 20.0, 12.0], b: [50.0, 22.0, 10.0], radius: 3.0 },
            // A sealed pocket, entirely in rock.
            Capsule { a: [40.0, 8.0, 5.0], b: [44.0, 8.0, 5.0], radius: 2.0 },
        ],
        ..SdfModel::new(
            Domain { min: [0.0, 0.0, 0.0], max: [60.0, 40.0, 30.0] },
            TerrainField::Plane { elevation: 25.0, origin: [0.0, 0.0], gradient: [0.05, 0.02] },
        )
    }
}

/// A seeded tangle of 80 conduits (random walks of capsules) under a tilted plane.
fn random_model() -> SdfModel {
    let mut state = 0x5eed_u64;
    let mut next = move || {
        state = state.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
        (state >> 11) as f64 / (1u64 << 53) as f64
    };
    let mut capsules = Vec::new();
    for _ in 0..8 {
        let mut p = DVec3::new(next() * 80.0 + 10.0, next() * 80.0 + 10.0, next() * 30.0 + 5.0);
        for _ in 0..10 {
            let q = p + DVec3::new(next() - 0.5, next() - 0.5, (next() - 0.5) * 0.4) * 16.0;
            capsules.push(Capsule { a: p.to_array(), b: q.to_array(), radius: 0.8 + next() * 2.0 });
            p = q;
        }
    }
    SdfModel {
        capsules,
        ..SdfModel::new(
            Domain { min: [0.0, 0.0, 0.0], max: [100.0, 100.0, 45.0] },
            TerrainField::Plane { elevation: 38.0, origin: [0.0, 0.0], gradient: [0.03, -0.02] },
        )
    }
}

fn with_threads<T: Send>(threads: usize, f: impl FnOnce() -> T + Send) -> T {
    rayon::ThreadPoolBuilder::new().num_threads(threads).build().unwrap().install(f)
}

fn mesh_of(model: SdfModel, cell: f64) -> Mesh {
    mesh_field(&CarvedTerrain::new(model), cell, &[])
}

fn assert_watertight(name: &str, surface: &TriMesh) {
    assert!(!surface.triangles.is_empty(), "{name}: empty");
    if let Err(defect) = watertight::check(surface) {
        panic!("{name}: {defect}");
    }
    assert!(surface.enclosed_volume() > 0.0, "{name}: volume {}", surface.enclosed_volume());
}

#[test]
fn both_surfaces_are_closed_oriented_manifolds() {
    for (name, model, cell) in [("fixed", model(), 1.0), ("random", random_model(), 0.7)] {
        let mesh = with_threads(2, || mesh_of(model, cell));
        assert_watertight(&format!("{name} terrain"), &mesh.terrain);
        assert_watertight(&format!("{name} cave"), &mesh.cave);
    }
}

#[test]
fn the_checker_finds_holes_flips_and_degenerate_triangles() {
    let mesh = mesh_of(model(), 2.0);
    let mut open = mesh.terrain.clone();
    open.triangles.pop();
    assert!(matches!(watertight::check(&open), Err(watertight::Defect::OpenEdge(..))));
    let mut flipped = mesh.terrain.clone();
    flipped.triangles[0].swap(1, 2);
    assert!(watertight::check(&flipped).is_err());
    let mut flat = mesh.terrain.clone();
    let t = flat.triangles[0];
    flat.vertices[t[1] as usize] = flat.vertices[t[0] as usize];
    assert!(watertight::check(&flat).is_err());
}

#[test]
fn rock_and_cave_fill_the_ground_between_them() {
    let mesh = mesh_of(model(), 0.5);
    let under_terrain: f64 = 60.0 * 40.0 * (25.0 + 0.05 * 30.0 + 0.02 * 20.0);
    let (rock, cave) = (mesh.terrain.enclosed_volume(), mesh.cave.enclosed_volume());
    assert!(((rock + cave) / under_terrain - 1.0).abs() < 1e-3, "{rock} + {cave} vs {under_terrain}");
    // The open conduits: π·2.5²·16.8 + π·3²·35.1 + a half ball of 3 m, less their top above
    // the ground and the overlap at the bend.
    assert!(cave > 1250.0 && cave < 1400.0, "{cave}");
}

#[test]
fn sealed_pocket_is_removed_unless_it_holds_a_spring() {
    let field = CarvedTerrain::new(model());
    let mesh = mesh_field(&field, 0.5, &[]);
    let pocket = PI * 4.0 * 4.0 + 4.0 / 3.0 * PI * 8.0;
    // Marching cubes' chords cut inside a convex surface: a capsule of 2 m radius at 0.5 m
    // loses about 2 % of its volume.
    for removed in [mesh.terrain.removed, mesh.cave.removed] {
        assert_eq!((removed.islands, removed.pockets), (0, 1));
        assert!((removed.pocket_volume / pocket - 1.0).abs() < 0.03, "{removed:?}");
    }
    let spring = DVec3::new(42.0, 8.0, 5.0);
    let kept = mesh_field(&field, 0.5, &[spring]);
    assert_eq!(kept.terrain.removed.pockets + kept.cave.removed.pockets, 0);
    let gained = kept.cave.enclosed_volume() - mesh.cave.enclosed_volume();
    assert!((gained / pocket - 1.0).abs() < 0.03, "{gained}");
}

#[test]
fn a_capsule_matches_its_analytic_area_and_volume() {
    let (r, length) = (2.0, 10.0);
    let field = CarvedTerrain::new(SdfModel {
        capsules: vec![Capsule { a: [4.3, 5.1, 4.7], b: [4.3 + length, 5.1, 4.7], radius: r }],
        ..SdfModel::new(
            Domain { min: [0.0, 0.0, 0.0], max: [20.0, 10.0, 10.0] },
            TerrainField::Plane { elevation: 9.0, origin: [0.0, 0.0], gradient: [0.0, 0.0] },
        )
    });
    let cave = polygonize(&Cave(&field), 0.05);
    let area = 2.0 * PI * r * length + 4.0 * PI * r * r;
    let volume = PI * r * r * length + 4.0 / 3.0 * PI * r * r * r;
    assert!((cave.area() / area - 1.0).abs() < 0.01, "area {} vs {area}", cave.area());
    assert!(
        (cave.enclosed_volume() / volume - 1.0).abs() < 0.01,
        "volume {} vs {volume}",
        cave.enclosed_volume()
    );
}

#[test]
fn one_or_two_threads_make_the_same_mesh() {
    let [one, two] = [1, 2].map(|threads| {
        with_threads(threads, || {
            let field = CarvedTerrain::new(random_model());
            // Cave and water finer than the terrain, as the stage's automatic cave cell does.
            karst_mesher::mesh_with(&field, 1.0, 0.6, &[])
        })
    });
    assert!(one == two, "the mesh differs between 1 and 2 threads");
}

/// A field with every value exact (no reach-limited search).
struct Exact<V>(V);

impl<V: Volume> Volume for Exact<V> {
    fn eval(&self, p: DVec3) -> f64 {
        self.0.eval(p)
    }

    fn extent(&self) -> (DVec3, DVec3) {
        self.0.extent()
    }
}

#[test]
fn reach_limited_values_give_the_exact_mesh() {
    let field = CarvedTerrain::new(random_model());
    same_surface(polygonize(&Cave(&field), 0.8), polygonize(&Exact(Cave(&field)), 0.8));
    same_surface(polygonize(&field, 0.8), polygonize(&Exact(&field), 0.8));
}

/// The same vertices and triangles, the reach-limited field's (which also bounds boxes by its
/// leaves' boxes) found with no more evaluations than the exact one's.
fn same_surface(limited: TriMesh, exact: TriMesh) {
    assert!(!limited.triangles.is_empty());
    assert_eq!((&limited.vertices, &limited.triangles), (&exact.vertices, &exact.triangles));
    assert!(limited.field_evaluations <= exact.field_evaluations);
}

#[test]
fn simplification_keeps_the_promises() {
    let mesh = mesh_of(random_model(), 0.7);
    for (name, surface) in [("terrain", &mesh.terrain), ("cave", &mesh.cave)] {
        let target = surface.triangles.len() / 2;
        let mut simple = surface.clone();
        karst_mesher::simplify(&mut simple, target);
        assert!(simple.triangles.len() <= target, "{name}: {} > {target}", simple.triangles.len());
        assert_watertight(&format!("simplified {name}"), &simple);
        let (before, after) = (surface.enclosed_volume(), simple.enclosed_volume());
        assert!((after / before - 1.0).abs() < 0.03, "{name}: volume {before} → {after}");
        let (before, after) = (surface.area(), simple.area());
        assert!((after / before - 1.0).abs() < 0.05, "{name}: area {before} → {after}");
    }
}

/// Rock with a hollow shell of air (3 m to 6 m around a centre) opened to the sky by a shaft:
/// the ball inside the shell is a rock island floating in cave air.
struct HollowShell {
    model: SdfModel,
    cave: bool,
}

impl HollowShell {
    const CENTRE: DVec3 = DVec3::new(30.0, 20.0, 12.0);
}

impl Volume for HollowShell {
    fn eval(&self, p: DVec3) -> f64 {
        let ground = self.model.terrain.distance(p).max(self.model.domain.signed_distance(p));
        let d = p.distance(Self::CENTRE);
        let shell = (3.0 - d).max(d - 6.0);
        let shaft = Capsule { a: [30.0, 20.0, 17.5], b: [30.0, 20.0, 40.0], radius: 1.5 }.distance(p);
        let air = shell.min(shaft);
        if self.cave { air.max(ground) } else { ground.max(-air) }
    }

    fn extent(&self) -> (DVec3, DVec3) {
        (self.model.domain.min(), self.model.domain.max())
    }
}

#[test]
fn rock_island_in_cave_air_is_removed_from_both_surfaces() {
    let island = 4.0 / 3.0 * PI * 27.0;
    for (cave, solid) in [(false, Solid::Rock), (true, Solid::Cave)] {
        let model = SdfModel { capsules: Vec::new(), ..model() };
        let volume = HollowShell { model: model.clone(), cave };
        let mut surface = polygonize(&volume, 0.4);
        assert_eq!(components::count(&surface), 2, "the ground (or the open shell) and the island");
        clean(&mut surface, solid, &model, &[], 0.4);
        assert_eq!((surface.removed.islands, surface.removed.pockets), (1, 0), "{solid:?}");
        assert!((surface.removed.island_volume / island - 1.0).abs() < 0.03, "{:?}", surface.removed);
        assert_eq!(components::count(&surface), 1);
        assert_watertight(&format!("{solid:?} without the island"), &surface);
    }
}

/// Random signs on the lattice points of a box (air outside it): every marching-cubes case,
/// ambiguous faces included, in every neighbourhood. Not a distance field, so nothing is
/// pruned.
struct RandomSigns;

impl Volume for RandomSigns {
    fn eval(&self, p: DVec3) -> f64 {
        if p.min_element() < 0.5 || p.max_element() > 11.5 {
            return 1.0;
        }
        let [i, j, k] = p.round().as_ivec3().to_array();
        let mut h =
            (i as u64).wrapping_mul(0x9e37_79b9_7f4a_7c15) ^ (j as u64).wrapping_mul(0xc2b2_ae3d_27d4_eb4f);
        h ^= (k as u64).wrapping_mul(0x1656_67b1_9e37_79f9);
        h ^= h >> 29;
        h = h.wrapping_mul(0xbf58_476d_1ce4_e5b9);
        h ^= h >> 32;
        // Values in (−1, 1) away from 0, so that vertices are spread along their edges.
        let u = (h >> 11) as f64 / (1u64 << 53) as f64;
        if u < 0.5 { -0.1 - u } else { u - 0.4 }
    }

    fn bound(&self, _lo: DVec3, _hi: DVec3) -> f64 {
        0.0
    }

    fn extent(&self) -> (DVec3, DVec3) {
        (DVec3::ZERO, DVec3::splat(12.0))
    }
}

#[test]
fn random_signs_give_a_closed_oriented_manifold() {
    let surface = polygonize(&RandomSigns, 1.0);
    assert!(surface.triangles.len() > 1000, "{}", surface.triangles.len());
    if let Err(defect) = watertight::check(&surface) {
        panic!("{defect}");
    }
    // Every vertex lies on one lattice edge: no two coincide.
    let mut positions: Vec<[u32; 3]> = surface.vertices.iter().map(|v| v.map(f32::to_bits)).collect();
    positions.sort_unstable();
    assert!(positions.windows(2).all(|w| w[0] != w[1]));
    let two = with_threads(2, || polygonize(&RandomSigns, 1.0));
    assert_eq!(surface, two);
}

#[test]
fn thin_conduits_are_meshed_whole_at_the_automatic_cave_cell() {
    // A 1.6 m wide conduit, winding across a domain meshed at 4 m: at 4 m its cave mesh breaks
    // into pieces (or vanishes), at the automatic cave cell it is one closed tube.
    let (r, a, b, c) = (0.8, [5.3, 20.1, 10.2], [45.7, 21.3, 9.1], [75.2, 48.9, 11.4]);
    let model = SdfModel {
        capsules: vec![Capsule { a, b, radius: r }, Capsule { a: b, b: c, radius: r }],
        ..SdfModel::new(
            Domain { min: [0.0, 0.0, 0.0], max: [80.0, 60.0, 20.0] },
            TerrainField::Plane { elevation: 18.0, origin: [0.0, 0.0], gradient: [0.0, 0.0] },
        )
    };
    let cave_cell = karst_mesher::cave_cell(&model, 4.0, 0.0);
    assert_eq!(cave_cell, r);
    let field = CarvedTerrain::new(model);
    let coarse = polygonize(&Cave(&field), 4.0);
    assert!(components::count(&coarse) != 1, "a 4 m lattice should miss parts of it");
    let mesh = karst_mesher::mesh_with(&field, 4.0, cave_cell, &[DVec3::from_array(a)]);
    assert_watertight("cave", &mesh.cave);
    assert_eq!(components::count(&mesh.cave), 1);
    let length = DVec3::from_array(a).distance(DVec3::from_array(b))
        + DVec3::from_array(b).distance(DVec3::from_array(c));
    let volume = PI * r * r * length;
    // One cell per radius: marching cubes' chords keep about 80 % of the tube.
    let ratio = mesh.cave.enclosed_volume() / volume;
    assert!(ratio > 0.7 && ratio < 1.0, "{} vs {volume}", mesh.cave.enclosed_volume());
}

#[test]
fn a_conduit_thinner_than_the_automatic_cave_cell_is_meshed_one_cell_thick_and_whole() {
    // 150 m of 2 m passages and 40 m of a 0.3 m one joining them: the cell follows the
    // passages (the length-weighted median, 2 m), not the thin one; the thin one, which a 2 m
    // lattice misses, is meshed a cell thick and the cave is one closed surface.
    let wide = 2.0;
    let (a, b, c, d) = ([5.0, 20.0, 10.0], [80.0, 20.0, 10.0], [155.0, 20.0, 10.0], [80.0, 60.3, 11.1]);
    let model = SdfModel {
        capsules: vec![
            Capsule { a, b, radius: wide },
            Capsule { a: b, b: c, radius: wide },
            Capsule { a: b, b: d, radius: 0.3 },
        ],
        ..SdfModel::new(
            Domain { min: [0.0, 0.0, 0.0], max: [160.0, 70.0, 20.0] },
            TerrainField::Plane { elevation: 18.0, origin: [0.0, 0.0], gradient: [0.0, 0.0] },
        )
    };
    let cave_cell = karst_mesher::cave_cell(&model, 4.0, 0.0);
    assert_eq!(cave_cell, wide);
    let true_size = CarvedTerrain::new(model.clone());
    let missed = polygonize(&Cave(&true_size), cave_cell);
    let field = karst_mesher::meshed_field(&model, cave_cell);
    let mesh = karst_mesher::mesh_with(&field, 4.0, cave_cell, &[DVec3::from_array(a)]);
    assert_watertight("cave", &mesh.cave);
    assert_eq!(components::count(&mesh.cave), 1);
    // The thin conduit's end, 40 m from the junction, is in the cave mesh: its box reaches it.
    let reach = mesh.cave.vertices.iter().map(|v| v[1] as f64).fold(f64::MIN, f64::max);
    assert!(reach > d[1] + 0.5 * cave_cell, "{reach}");
    let missed_reach = missed.vertices.iter().map(|v| v[1] as f64).fold(f64::MIN, f64::max);
    assert!(missed_reach < d[1], "a 2 m lattice should miss most of the 0.3 m conduit: {missed_reach}");
}

/// An `nx` × `ny` heightfield of 8 m pixels centred on the domain's 8 m grid: hills and
/// valleys about 30 m up, rising by `slope` towards +x.
fn hills(nx: u32, ny: u32, slope: f64) -> karst_geology::heightfield::HeightGrid {
    let heights = (0..ny)
        .flat_map(|j| {
            (0..nx).map(move |i| {
                let (x, y) = (i as f64 * 8.0, j as f64 * 8.0);
                30.0 + 6.0 * (x / 25.0).sin() * (y / 31.0).cos() + slope * x
            })
        })
        .collect();
    karst_geology::heightfield::HeightGrid::new([-4.0, -4.0], 8.0, nx, ny, heights)
}

/// A 120 × 100 m heightfield of 8 m pixels (two hills and a valley), a conduit that opens in
/// the valley floor and a sealed one deep below.
fn raster_model() -> SdfModel {
    let grid = hills(17, 15, 0.04);
    SdfModel {
        capsules: vec![
            Capsule { a: [60.0, 50.0, 40.0], b: [62.0, 48.0, 15.0], radius: 2.0 },
            Capsule { a: [62.0, 48.0, 15.0], b: [95.0, 40.0, 12.0], radius: 2.5 },
            Capsule { a: [20.0, 20.0, 6.0], b: [30.0, 22.0, 6.0], radius: 1.5 },
        ],
        ..SdfModel::new(Domain { min: [0.0, 0.0, 0.0], max: [120.0, 100.0, 50.0] }, TerrainField::Grid(grid))
    }
}

#[test]
fn a_raster_terrain_is_meshed_coarsely_away_from_its_openings_and_stays_closed() {
    let field = CarvedTerrain::new(raster_model());
    let lattice = karst_mesher::TerrainLattice::of(&field, 1.0).expect("8 m pixels over 1 m cells");
    assert_eq!(lattice.ratio, 8);
    // Coarse planes only (every 8th, and three at each end), one fine patch round the opening.
    let cells = lattice.cells();
    assert_eq!(cells[0], 19, "planes 0, 1, 2, 8, 16, …, 120, 121, 122: {cells:?}");
    assert_eq!(lattice.patches.len(), 1);
    let patch = &lattice.patches[0];
    let [xs, ys, _] = &patch.lattice.planes;
    assert!(xs[0] < 60.5 && 60.5 < xs[xs.len() - 1] && ys[0] < 49.0 && 49.0 < ys[ys.len() - 1]);
    assert!(xs.windows(2).all(|w| w[1] - w[0] == 1.0), "fine in x across the patch");
    assert!(xs[xs.len() - 1] - xs[0] < 60.0, "the patch is local: {:?}", (xs[0], xs[xs.len() - 1]));
    assert!(karst_mesher::polygonize_patched(&field, &lattice).is_ok(), "the patch's rim is stitched");

    let coarse = with_threads(2, || karst_mesher::polygonize_terrain(&field, 1.0));
    let mut cleaned = coarse.clone();
    clean(&mut cleaned, Solid::Rock, field.model(), &[], 1.0);
    assert_watertight("raster terrain", &coarse);
    assert_watertight("raster terrain, cleaned", &cleaned);
    assert_eq!(components::count(&cleaned), 1, "the sealed conduit is filled, the opening kept");
    let uniform = polygonize(&field, 1.0);
    assert!(
        coarse.triangles.len() * 4 < uniform.triangles.len(),
        "{} vs {} triangles",
        coarse.triangles.len(),
        uniform.triangles.len()
    );
    // The same solid: the rock's volume (less the sealed conduit, in both) within 1.5 % (the
    // coarse cells are 8 m in z too: the ground away from the patch is 0.9 % low, mostly the
    // chamfer along the walls' tops); and the plain ground's coarse mesh less the opening, its
    // shaft and the conduit that the patch meshes under it (467 m³).
    let mut uniform_cleaned = uniform.clone();
    clean(&mut uniform_cleaned, Solid::Rock, field.model(), &[], 1.0);
    let (a, b) = (cleaned.enclosed_volume(), uniform_cleaned.enclosed_volume());
    assert!((a - b).abs() < 0.015 * b, "{a} vs {b} m³");
    let plain = SdfModel { capsules: Vec::new(), ..raster_model() };
    let ground = karst_mesher::polygonize_terrain(&CarvedTerrain::new(plain), 1.0).enclosed_volume();
    assert!(a < ground && ground - a < 0.002 * ground, "{a} vs {ground} m³ of plain ground");
    // The opening: the terrain's surface goes down the shaft, below the valley floor.
    let in_shaft = |m: &TriMesh| {
        m.vertices
            .iter()
            .filter(|v| (v[0] - 61.0).abs() < 2.0 && (v[1] - 49.0).abs() < 2.0 && v[2] < 22.0)
            .count()
    };
    assert!(in_shaft(&cleaned) > 10, "{} vertices down the shaft", in_shaft(&cleaned));
    let one = with_threads(1, || karst_mesher::polygonize_terrain(&field, 1.0));
    assert_eq!((one.vertices, one.triangles), (coarse.vertices, coarse.triangles));
}

/// A 320 × 240 m heightfield of 8 m pixels and vertical shafts opening at `openings`.
fn raster_with_shafts(openings: &[[f64; 2]]) -> SdfModel {
    let grid = hills(42, 32, 0.02);
    SdfModel {
        capsules: openings
            .iter()
            .map(|&[x, y]| Capsule { a: [x, y, 45.0], b: [x, y, 12.0], radius: 2.0 })
            .collect(),
        ..SdfModel::new(Domain { min: [0.0, 0.0, 0.0], max: [320.0, 240.0, 50.0] }, TerrainField::Grid(grid))
    }
}

#[test]
fn two_far_apart_openings_do_not_refine_the_ground_between_them() {
    let triangles = |openings: &[[f64; 2]]| {
        let field = CarvedTerrain::new(raster_with_shafts(openings));
        let lattice = karst_mesher::TerrainLattice::of(&field, 1.0).expect("8 m pixels over 1 m cells");
        assert_eq!(lattice.patches.len(), openings.len());
        let mesh = karst_mesher::polygonize_patched(&field, &lattice).expect("the rims are stitched");
        assert_watertight("raster terrain with shafts", &mesh);
        mesh.triangles.len() as f64
    };
    let (a, b) = ([60.0, 50.0], [250.0, 190.0]);
    let (none, one, other, both) = (triangles(&[]), triangles(&[a]), triangles(&[b]), triangles(&[a, b]));
    // Each opening adds its patch; together they add the sum, not the crossing of their slabs
    // (which would refine a 2 × 30 m wide cross through the whole domain).
    let sum = none + (one - none) + (other - none);
    assert!(one > none * 1.2 && other > none * 1.2, "{none} {one} {other}");
    assert!((both - sum).abs() < 0.03 * sum, "{both} vs {sum} = {none} + the two patches");
}

#[test]
fn an_opening_by_a_wall_is_a_fine_window_beside_the_patches_and_the_terrain_stays_closed() {
    // The shaft 4 m from the west wall: no patch can stand inside the wall there, so its cut is
    // a fine window of whole slabs; the other opening is a patch.
    let field = CarvedTerrain::new(raster_with_shafts(&[[4.0, 120.0], [250.0, 190.0]]));
    let lattice = karst_mesher::TerrainLattice::of(&field, 1.0).expect("8 m pixels over 1 m cells");
    assert_eq!(lattice.patches.len(), 1);
    let fine_at = |x: f64| lattice.planes[0].windows(2).any(|w| w[0] <= x && x < w[1] && w[1] - w[0] == 1.0);
    assert!(fine_at(4.5) && !fine_at(120.5), "the wall's shaft is a window, the middle coarse");
    let mesh = karst_mesher::polygonize_patched(&field, &lattice).expect("the rim is stitched");
    assert_watertight("raster terrain, a window and a patch", &mesh);
    let one = with_threads(1, || karst_mesher::polygonize_terrain(&field, 1.0));
    let two = with_threads(2, || karst_mesher::polygonize_terrain(&field, 1.0));
    assert_eq!((&one.vertices, &one.triangles), (&mesh.vertices, &mesh.triangles));
    assert_eq!((one.vertices, one.triangles), (two.vertices, two.triangles));
}
