//! The mesher's budget case: a seeded synthetic model of about 30k capsules in a
//! 1 × 1 × 0.4 km³ domain, as in Paris et al. 2021 §7.5 (the presets' own meshes are timed with
//! their scenes), and the same density of conduits in 2 × 2 × 0.4 km³. The whole domains are
//! meshed once in memory and once streamed to files ([`Spill`]), where the peak memory is that
//! of the polygonizer's front of slabs.

use std::fs::File;
use std::io::{BufReader, BufWriter, Read, Write};
use std::path::PathBuf;
use std::time::Instant;

use glam::DVec3;
use karst_geology::Domain;
use karst_mesher::{Cave, Volume};
use karst_mesher::{MeshSink, TriMesh, polygonize, polygonize_into};
use karst_scene::rng::Random;
use karst_sdf::{Capsule, CarvedTerrain, SdfModel, TerrainField};
use karst_stage::StageError;

/// Conduits per km² × segments per conduit = primitives per km².
const CONDUITS: usize = 300;
const SEGMENTS: usize = 100;

/// A `side` × `side` × 400 m domain with 300 conduits of 100 capsules per km²: persistent
/// random walks of 4–8 m steps, mostly along bedding (small vertical component), radii
/// 0.8–2.5 m, between 20 m and 360 m up.
pub fn model(seed: u64, side: f64) -> SdfModel {
    let domain = Domain { min: [0.0, 0.0, 0.0], max: [side, side, 400.0] };
    let conduits = (CONDUITS as f64 * (side / 1000.0).powi(2)).round() as usize;
    let mut random = Random::stream(seed, "bench", "synthetic conduits");
    let mut capsules = Vec::with_capacity(conduits * SEGMENTS);
    for _ in 0..conduits {
        let mut p = DVec3::new(
            random.range(20.0, side - 20.0),
            random.range(20.0, side - 20.0),
            random.range(20.0, 360.0),
        );
        let mut heading = random.range(0.0, std::f64::consts::TAU);
        let radius = random.range(0.8, 2.5);
        for _ in 0..SEGMENTS {
            heading += random.range(-0.5, 0.5);
            let step = random.range(4.0, 8.0);
            let d = DVec3::new(heading.cos(), heading.sin(), random.range(-0.15, 0.15)) * step;
            let q = (p + d).clamp(DVec3::new(5.0, 5.0, 20.0), DVec3::new(side - 5.0, side - 5.0, 360.0));
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

    fn bounds(&self, lo: DVec3, hi: DVec3, boxes: &[(DVec3, DVec3)], out: &mut [f64]) {
        self.inner.bounds(lo, hi, boxes, out)
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

/// Times the synthetic cases whose name contains `only` (all when None), `runs` times each.
pub fn run(runs: usize, only: Option<&str>) -> Result<Vec<Case>, StageError> {
    let wanted = |name: &str| only.is_none_or(|o| name.contains(o));
    let start = Instant::now();
    let field = CarvedTerrain::new(model(1, 1000.0));
    eprintln!(
        "synthetic model: {} capsules in {:.2} s",
        field.model().capsules.len(),
        start.elapsed().as_secs_f64()
    );
    let (lo, hi) = (DVec3::new(437.5, 437.5, 0.0), DVec3::new(562.5, 562.5, 400.0));
    let in_memory: [(&str, usize, &dyn Fn() -> TriMesh); 4] = [
        ("tile 125x125x400 m, carved terrain, 0.5 m", runs, &|| {
            polygonize(&Tile { inner: &field, lo, hi }, 0.5)
        }),
        ("tile 125x125x400 m, cave alone, 0.5 m", runs, &|| {
            polygonize(&Tile { inner: Cave(&field), lo, hi }, 0.5)
        }),
        ("whole 1x1x0.4 km, cave alone, 2 m", runs, &|| polygonize(&Cave(&field), 2.0)),
        // The budget case itself, once per bench (about 16 CPU-seconds and 1 GB).
        ("whole 1x1x0.4 km, carved terrain, 0.5 m", 1, &|| polygonize(&field, 0.5)),
    ];
    let mut cases: Vec<Case> = in_memory
        .into_iter()
        .filter(|(name, ..)| wanted(name))
        .map(|(name, runs, mesh)| time(name, runs, mesh))
        .collect();
    let name = "streamed 1x1x0.4 km, carved terrain, 0.5 m";
    if wanted(name) {
        cases.push(time_streamed(name, |sink| polygonize_into(&field, 0.5, sink))?);
    }
    let name = "streamed 2x2x0.4 km, carved terrain, 0.5 m";
    if wanted(name) {
        drop(field);
        let field = CarvedTerrain::new(model(1, 2000.0));
        eprintln!("synthetic model, 2 x 2 km: {} capsules", field.model().capsules.len());
        cases.push(time_streamed(name, |sink| polygonize_into(&field, 0.5, sink))?);
    }
    Ok(cases)
}

fn time(name: &str, runs: usize, mesh: &dyn Fn() -> TriMesh) -> Case {
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

/// One run of `mesh` into a [`Spill`]; the hash is that of the mesh the files hold, read back
/// after the run, so it equals the in-memory case's.
fn time_streamed(name: &str, mesh: impl Fn(&mut Spill) -> std::io::Result<u64>) -> Result<Case, StageError> {
    let dir = std::env::temp_dir().join(format!("karstgen-bench-mesh-{}", std::process::id()));
    let result = (|| -> std::io::Result<Case> {
        std::fs::create_dir_all(&dir)?;
        let mut spill = Spill::create(dir.clone())?;
        reset_peak_memory();
        let (start, cpu_start) = (Instant::now(), super::probes::cpu_seconds());
        let evaluations = mesh(&mut spill)?;
        let (vertices, triangles) = spill.finish()?;
        let seconds = start.elapsed().as_secs_f64();
        let cpu_seconds = super::probes::cpu_seconds().zip(cpu_start).map(|(end, start)| end - start);
        let peak_mb = peak_memory_mb();
        let hash = Spill::hash(&dir)?;
        Ok(Case {
            name: name.to_string(),
            seconds,
            cpu_seconds,
            triangles,
            evaluations_per_vertex: evaluations as f64 / vertices.max(1) as f64,
            peak_mb,
            hash,
        })
    })();
    let _ = std::fs::remove_dir_all(&dir);
    let case =
        result.map_err(|e| StageError::failure(format!("{}: cannot spill the mesh: {e}", dir.display())))?;
    eprintln!("{name}: {:.3} s", case.seconds);
    Ok(case)
}

/// A [`MeshSink`] writing the vertices (little-endian f32 triples) and the triangles
/// (little-endian u32 triples) to two files in a folder, as they come.
struct Spill {
    vertices: BufWriter<File>,
    triangles: BufWriter<File>,
    counts: (usize, usize),
    bytes: Vec<u8>,
}

impl Spill {
    const FILES: [&str; 2] = ["vertices.bin", "triangles.bin"];

    fn create(dir: PathBuf) -> std::io::Result<Self> {
        let open = |name: &str| File::create(dir.join(name)).map(|f| BufWriter::with_capacity(1 << 20, f));
        Ok(Spill {
            vertices: open(Self::FILES[0])?,
            triangles: open(Self::FILES[1])?,
            counts: (0, 0),
            bytes: Vec::new(),
        })
    }

    /// Flushes both files; returns the numbers of vertices and triangles.
    fn finish(mut self) -> std::io::Result<(usize, usize)> {
        self.vertices.flush()?;
        self.triangles.flush()?;
        Ok(self.counts)
    }

    /// [`mesh_hash`] of the mesh in `dir`'s files.
    fn hash(dir: &std::path::Path) -> std::io::Result<u64> {
        let mut h = FNV_OFFSET;
        for name in Self::FILES {
            let mut reader = BufReader::with_capacity(1 << 20, File::open(dir.join(name))?);
            let mut word = [0u8; 4];
            loop {
                match reader.read_exact(&mut word) {
                    Ok(()) => h = fnv(h, u32::from_le_bytes(word)),
                    Err(e) if e.kind() == std::io::ErrorKind::UnexpectedEof => break,
                    Err(e) => return Err(e),
                }
            }
        }
        Ok(h)
    }
}

impl MeshSink for Spill {
    type Error = std::io::Error;

    fn vertices(&mut self, vertices: &[[f32; 3]]) -> std::io::Result<()> {
        self.counts.0 += vertices.len();
        self.bytes.clear();
        self.bytes.extend(vertices.iter().flatten().flat_map(|c| c.to_le_bytes()));
        self.vertices.write_all(&self.bytes)
    }

    fn triangles(&mut self, triangles: &[[u32; 3]]) -> std::io::Result<()> {
        self.counts.1 += triangles.len();
        self.bytes.clear();
        self.bytes.extend(triangles.iter().flatten().flat_map(|v| v.to_le_bytes()));
        self.triangles.write_all(&self.bytes)
    }
}

const FNV_OFFSET: u64 = 0xcbf2_9ce4_8422_2325;

fn fnv(h: u64, word: u32) -> u64 {
    (h ^ word as u64).wrapping_mul(0x0100_0000_01b3)
}

/// FNV-1a over the vertex coordinates' bits and the triangles' indices.
fn mesh_hash(surface: &TriMesh) -> u64 {
    let words = surface.vertices.iter().flat_map(|v| v.map(f32::to_bits));
    let words = words.chain(surface.triangles.iter().flatten().copied());
    words.fold(FNV_OFFSET, fnv)
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
