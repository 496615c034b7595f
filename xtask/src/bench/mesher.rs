//! The mesher's budget case: a seeded synthetic model of about 30k capsules in a
//! 1 × 1 × 0.4 km³ domain, as in Paris et al. 2021 §7.5 (the presets' own meshes are timed with
//! their scenes).

use std::time::Instant;

use glam::DVec3;
use karst_geology::Domain;
use karst_geology::rng::Random;
use karst_mesher::TriMesh;
use karst_mesher::polygonize;
use karst_mesher::{Cave, Volume};
use karst_sdf::{Capsule, CarvedTerrain, SdfModel, TerrainField};

/// Conduits × segments per conduit = primitives.
const CONDUITS: usize = 300;
const SEGMENTS: usize = 100;

/// 300 conduits of 100 capsules: persistent random walks of 4–8 m steps, mostly along
/// bedding (small vertical component), radii 0.8–2.5 m, between 20 m and 360 m up.
pub fn model(seed: u64) -> SdfModel {
    let domain = Domain { min: [0.0, 0.0, 0.0], max: [1000.0, 1000.0, 400.0] };
    let mut random = Random::stream(seed, "bench", "synthetic conduits");
    let mut capsules = Vec::with_capacity(CONDUITS * SEGMENTS);
    for _ in 0..CONDUITS {
        let mut p =
            DVec3::new(random.range(20.0, 980.0), random.range(20.0, 980.0), random.range(20.0, 360.0));
        let mut heading = random.range(0.0, std::f64::consts::TAU);
        let radius = random.range(0.8, 2.5);
        for _ in 0..SEGMENTS {
            heading += random.range(-0.5, 0.5);
            let step = random.range(4.0, 8.0);
            let d = DVec3::new(heading.cos(), heading.sin(), random.range(-0.15, 0.15)) * step;
            let q = (p + d).clamp(DVec3::new(5.0, 5.0, 20.0), DVec3::new(995.0, 995.0, 360.0));
            capsules.push(Capsule {
                a: p.to_array(),
                b: q.to_array(),
                radius: radius * random.range(0.8, 1.2),
            });
            p = q;
        }
    }
    let terrain = TerrainField::Plane { elevation: 390.0, origin: [0.0, 0.0], gradient: [0.004, -0.003] };
    SdfModel { capsules, ..SdfModel::new(domain, terrain) }
}

/// A column of the domain: the field of `inner`, meshed only over [lo, hi].
struct Tile<V> {
    inner: V,
    lo: DVec3,
    hi: DVec3,
}

impl<V: Volume> Volume for Tile<V> {
    fn eval(&self, p: DVec3) -> f64 {
        self.inner.eval(p)
    }

    fn eval_within(&self, p: DVec3, reach: f64) -> f64 {
        self.inner.eval_within(p, reach)
    }

    fn eval_block(&self, lo: DVec3, hi: DVec3, reach: f64, points: &[DVec3], out: &mut Vec<f64>) {
        self.inner.eval_block(lo, hi, reach, points, out)
    }

    fn bound(&self, lo: DVec3, hi: DVec3) -> f64 {
        self.inner.bound(lo, hi)
    }

    fn extent(&self) -> (DVec3, DVec3) {
        (self.lo, self.hi)
    }
}

/// One timed case: median seconds, the mesh's size and cost, and the peak resident memory
/// while meshing, MB.
pub struct Case {
    pub name: String,
    pub seconds: f64,
    /// Median CPU seconds (user + system, all threads) of a run.
    pub cpu_seconds: Option<f64>,
    pub triangles: usize,
    pub evaluations_per_vertex: f64,
    pub peak_mb: f64,
    /// FNV-1a of the vertices' and triangles' bytes: equal hashes, equal meshes.
    pub hash: u64,
}

/// Times the synthetic cases, `runs` times each.
pub fn run(runs: usize) -> Vec<Case> {
    let start = Instant::now();
    let field = CarvedTerrain::new(model(1));
    eprintln!(
        "synthetic model: {} capsules in {:.2} s",
        field.model().capsules.len(),
        start.elapsed().as_secs_f64()
    );
    let (lo, hi) = (DVec3::new(437.5, 437.5, 0.0), DVec3::new(562.5, 562.5, 400.0));
    vec![
        time("tile 125x125x400 m, carved terrain, 0.5 m", runs, || {
            polygonize(&Tile { inner: &field, lo, hi }, 0.5)
        }),
        time("tile 125x125x400 m, cave alone, 0.5 m", runs, || {
            polygonize(&Tile { inner: Cave(&field), lo, hi }, 0.5)
        }),
        time("whole 1x1x0.4 km, cave alone, 2 m", runs, || polygonize(&Cave(&field), 2.0)),
        // The budget case itself, once per bench (about 25 CPU-seconds and 3 GB).
        time("whole 1x1x0.4 km, carved terrain, 0.5 m", 1, || polygonize(&field, 0.5)),
    ]
}

fn time(name: &str, runs: usize, mesh: impl Fn() -> TriMesh) -> Case {
    let mut seconds = Vec::new();
    let mut cpu = Vec::new();
    let mut surface = TriMesh::default();
    reset_peak_memory();
    for _ in 0..runs.max(1) {
        drop(std::mem::take(&mut surface));
        let (start, cpu_start) = (Instant::now(), super::probes::cpu_seconds());
        surface = mesh();
        seconds.push(start.elapsed().as_secs_f64());
        cpu.extend(super::probes::cpu_seconds().zip(cpu_start).map(|(end, start)| end - start));
    }
    let case = Case {
        name: name.to_string(),
        seconds: super::median(seconds),
        cpu_seconds: (!cpu.is_empty()).then(|| super::median(cpu)),
        triangles: surface.triangles.len(),
        evaluations_per_vertex: surface.evaluations_per_vertex(),
        peak_mb: peak_memory_mb(),
        hash: mesh_hash(&surface),
    };
    eprintln!("{name}: {:.3} s", case.seconds);
    case
}

/// FNV-1a over the vertex coordinates' bits and the triangles' indices.
fn mesh_hash(surface: &TriMesh) -> u64 {
    let words = surface.vertices.iter().flat_map(|v| v.map(f32::to_bits));
    let words = words.chain(surface.triangles.iter().flatten().copied());
    words.fold(0xcbf2_9ce4_8422_2325, |h, w| (h ^ w as u64).wrapping_mul(0x0100_0000_01b3))
}

/// Resets the kernel's peak resident set of this process (Linux; ignored elsewhere).
fn reset_peak_memory() {
    let _ = std::fs::write("/proc/self/clear_refs", "5");
}

/// Peak resident set since the last reset, MB (0 where unknown).
fn peak_memory_mb() -> f64 {
    let status = std::fs::read_to_string("/proc/self/status").unwrap_or_default();
    let kb = status
        .lines()
        .find_map(|l| l.strip_prefix("VmHWM:"))
        .and_then(|v| v.trim().trim_end_matches("kB").trim().parse::<f64>().ok())
        .unwrap_or(0.0);
    kb / 1024.0
}
