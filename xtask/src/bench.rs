//! `cargo xtask bench`: times every stage of the benchmark scenes, in process, and prints the
//! median of several runs per stage; then times the network statistics on real caves and
//! generated networks, beside karstnet 1.2.5 when `KARSTNET_PYTHON` names its interpreter.

use std::path::{Path, PathBuf};
use std::time::Instant;

use karst_artifact::{Stage, StageError};
use karst_metrics::{Network, characterize, readers};

use crate::executor::{Executor, InProcess};

/// Median seconds per stage over `runs` full pipeline runs of `scene`.
pub fn time_scene(scene: &Path, runs: usize) -> Result<Vec<(Stage, f64)>, StageError> {
    let out = scratch_dir(scene);
    let mut times: Vec<Vec<f64>> = vec![Vec::new(); Stage::ALL.len()];
    for _ in 0..runs.max(1) {
        for (i, stage) in Stage::ALL.into_iter().enumerate() {
            let start = Instant::now();
            InProcess.run(stage, scene, &out)?;
            times[i].push(start.elapsed().as_secs_f64());
        }
    }
    let _ = std::fs::remove_dir_all(&out);
    Ok(Stage::ALL.into_iter().zip(times.into_iter().map(median)).collect())
}

/// Median seconds of `stage` alone on `scene` over `runs` runs (the earlier stages run once
/// first), and the headline of its last run.
pub fn time_stage(scene: &Path, stage: Stage, runs: usize) -> Result<(f64, String), StageError> {
    let out = scratch_dir(scene);
    for earlier in Stage::ALL.into_iter().take_while(|s| *s != stage) {
        InProcess.run(earlier, scene, &out)?;
    }
    let mut times = Vec::new();
    let mut headline = String::new();
    for _ in 0..runs.max(1) {
        let start = Instant::now();
        headline = InProcess.run(stage, scene, &out)?;
        times.push(start.elapsed().as_secs_f64());
    }
    let _ = std::fs::remove_dir_all(&out);
    Ok((median(times), headline))
}

fn median(mut values: Vec<f64>) -> f64 {
    values.sort_by(f64::total_cmp);
    values[values.len() / 2]
}

fn scratch_dir(scene: &Path) -> PathBuf {
    let name = scene.file_stem().map(|s| s.to_string_lossy().into_owned()).unwrap_or_default();
    std::env::temp_dir().join(format!("karstgen-bench-{}-{name}", std::process::id()))
}

/// One cost-graph budget case: `samples` uniform random points (seeded) in the scene's domain,
/// `k` neighbours, the scene's geology and cost model. Only the graph build is timed.
pub struct CostgraphCase {
    pub samples: usize,
    pub k: usize,
}

/// What a cost-graph case measured: median seconds, edges, bytes per edge of the graph and the
/// process's peak resident memory during the builds (Linux; None elsewhere).
pub struct CostgraphTimes {
    pub seconds: f64,
    /// Median CPU seconds of the process (all threads) per build: on a shared machine, wall
    /// time over-states what the build needs.
    pub cpu_seconds: Option<f64>,
    pub edges: usize,
    pub bytes_per_edge: f64,
    pub peak_bytes: Option<u64>,
}

/// Times `case` under `scene` (median of `runs` builds).
pub fn time_costgraph(scene: &Path, case: &CostgraphCase, runs: usize) -> Result<CostgraphTimes, StageError> {
    let mut scene = karst_geology::Scene::load(scene)?;
    scene.costgraph.k = case.k;
    let mut rng = karst_geology::rng::Random::stream(scene.seed, "bench", "costgraph-points");
    let (min, max) = (scene.domain.min, scene.domain.max);
    let points: Vec<[f64; 3]> =
        (0..case.samples).map(|_| std::array::from_fn(|axis| rng.range(min[axis], max[axis]))).collect();
    reset_peak_memory();
    let mut times = Vec::new();
    let mut cpu = Vec::new();
    let mut last = None;
    for _ in 0..runs.max(1) {
        drop(last.take());
        let (start, cpu_start) = (Instant::now(), cpu_seconds());
        let graph = karst_costgraph::build_points(&scene, &points)?;
        times.push(start.elapsed().as_secs_f64());
        cpu.extend(cpu_seconds().zip(cpu_start).map(|(end, start)| end - start));
        last = Some(graph);
    }
    let graph = last.expect("at least one run");
    Ok(CostgraphTimes {
        seconds: median(times),
        cpu_seconds: (!cpu.is_empty()).then(|| median(cpu)),
        edges: graph.edge_count(),
        bytes_per_edge: graph.bytes_in_memory() as f64 / graph.edge_count().max(1) as f64,
        peak_bytes: peak_memory(),
    })
}

/// Resets the kernel's peak-RSS counter of this process (Linux ≥ 4.0).
pub(crate) fn reset_peak_memory() {
    let _ = std::fs::write("/proc/self/clear_refs", "5");
}

/// Peak resident memory of this process since the last reset, bytes.
pub(crate) fn peak_memory() -> Option<u64> {
    status_bytes("VmHWM:")
}

/// Resident memory of this process now, bytes.
pub(crate) fn resident_memory() -> Option<u64> {
    status_bytes("VmRSS:")
}

/// A `kB` line of /proc/self/status, in bytes.
fn status_bytes(key: &str) -> Option<u64> {
    let status = std::fs::read_to_string("/proc/self/status").ok()?;
    let line = status.lines().find(|l| l.starts_with(key))?;
    let kb: u64 = line.split_whitespace().nth(1)?.parse().ok()?;
    Some(kb * 1024)
}

/// User + system CPU seconds of this process so far (Linux; clock ticks of 1/100 s).
pub(crate) fn cpu_seconds() -> Option<f64> {
    let stat = std::fs::read_to_string("/proc/self/stat").ok()?;
    let fields: Vec<&str> = stat.rsplit_once(')')?.1.split_whitespace().collect();
    let ticks = |i: usize| fields.get(i)?.parse::<f64>().ok();
    Some((ticks(11)? + ticks(12)?) / 100.0)
}

/// Sampling radius of the KarstNSim skeleton budget case (the preset's 28 m × 0.39, about 100k
/// samples).
const KARSTNSIM_BENCH_RADIUS: f64 = 11.0;

/// The skeleton budgets of issue 5, timed apart from sampling and the cost graph: (case, samples,
/// median seconds). The γ-skeleton of the looping preset resampled to about 60k samples, and a
/// KarstNSim network of the karstnsim preset's 5 sinks and spring S1 on about 100k samples with
/// k = 50.
pub fn time_skeleton_budgets(runs: usize) -> Result<Vec<(String, usize, f64)>, StageError> {
    use karst_geology::{KeyPointKind, Scene};
    use karst_skeleton::search::EdgeCosts;
    use karst_skeleton::{assemble::NetworkBuilder, gamma, karstnsim, routing};

    let prepare = |path: &str, edit: &dyn Fn(&mut Scene)| -> Result<_, StageError> {
        let mut scene = Scene::load(Path::new(path))?;
        edit(&mut scene);
        let samples = karst_sampling::stage::sample_scene(&scene)?;
        let graph = karst_costgraph::build(&scene, &samples)?;
        Ok((scene, samples, graph))
    };
    let mut results = Vec::new();
    let (scene, samples, graph) = prepare("fixtures/scenes/looping.toml", &|s| s.sampling.radius = 8.8)?;
    let mut times = Vec::new();
    for _ in 0..runs.max(1) {
        let start = Instant::now();
        gamma::network(&scene, &samples, &graph, &mut NetworkBuilder::default())?;
        times.push(start.elapsed().as_secs_f64());
    }
    results.push(("γ-skeleton, looping preset (47 key points)".to_string(), samples.len(), median(times)));
    let one_spring = |s: &mut Scene| {
        s.keypoints.retain(|k| k.name != "S2");
        s.connectivity.matrix = None;
        // About 100k samples: every radius (the layers' too) scaled by the same factor.
        let scale = KARSTNSIM_BENCH_RADIUS / s.sampling.radius;
        s.sampling.radius = KARSTNSIM_BENCH_RADIUS;
        for radius in s.geology.layers.iter_mut().filter_map(|l| l.radius.as_mut()) {
            *radius *= scale;
        }
        s.costgraph.k = 50;
    };
    let (scene, samples, graph) = prepare("fixtures/scenes/karstnsim.toml", &one_spring)?;
    debug_assert_eq!(scene.keypoints_of(KeyPointKind::Spring).count(), 1);
    let cost_set = |_: &str| -> &dyn EdgeCosts { &graph };
    let phase = karstnsim::PhaseSetup::single(&scene, &graph);
    let mut times = Vec::new();
    for _ in 0..runs.max(1) {
        let start = Instant::now();
        karstnsim::route(&scene, &samples, &graph, &cost_set, &routing::sinks_in_order(&scene), &phase)?;
        times.push(start.elapsed().as_secs_f64());
    }
    results.push(("KarstNSim, 5 sinks, 1 spring, k = 50".to_string(), samples.len(), median(times)));
    Ok(results)
}

/// The sdf stage's budgets (issue 7) on one tree: build time, mean evaluation time and memory
/// per primitive.
pub struct SdfBench {
    pub primitives: usize,
    pub by_kind: Vec<(&'static str, usize)>,
    pub build_seconds: f64,
    pub eval_uniform_ns: f64,
    pub eval_near_ns: f64,
    /// The same in CPU time of the process (Linux): on a shared machine wall time also counts
    /// the waits for a core.
    pub eval_uniform_cpu_ns: Option<f64>,
    pub eval_near_cpu_ns: Option<f64>,
    /// [karst, water] in-memory bytes.
    pub memory_bytes: [usize; 2],
    pub artifact_bytes: u64,
}

/// Times `karst_sdf::build` and `CarvedTerrain::eval` on `conduits` synthetic conduits of 12
/// nodes: evaluations at 200k points uniform in the domain and 200k within 6 m of a node.
pub fn sdf_network(conduits: usize, runs: usize) -> Result<SdfBench, StageError> {
    let scene = karst_sdf::synthetic::scene();
    let (skeleton, hydro) = karst_sdf::synthetic::network(5, conduits, 12);
    sdf_tree(&scene, &skeleton, &hydro, runs)
}

/// The same on the tree of a preset scene: its stages up to hydro run once (not timed).
pub fn sdf_preset(scene: &Path, runs: usize) -> Result<SdfBench, StageError> {
    use karst_artifact::read_artifact;
    let out = scratch_dir(scene);
    for stage in [Stage::Sampling, Stage::Costgraph, Stage::Skeleton, Stage::Hydro] {
        InProcess.run(stage, scene, &out)?;
    }
    let (_, skeleton) = read_artifact::<karst_skeleton::Skeleton>(&out.join(Stage::Skeleton.file_name()))?;
    let (_, hydro) = read_artifact::<karst_hydro::Hydro>(&out.join(Stage::Hydro.file_name()))?;
    let _ = std::fs::remove_dir_all(&out);
    sdf_tree(&karst_geology::Scene::load(scene)?, &skeleton, &hydro, runs)
}

fn sdf_tree(
    scene: &karst_geology::Scene,
    skeleton: &karst_skeleton::Skeleton,
    hydro: &karst_hydro::Hydro,
    runs: usize,
) -> Result<SdfBench, StageError> {
    use glam::DVec3;
    use karst_sdf::{CarvedTerrain, build};

    let mut builds = Vec::new();
    let mut model = None;
    for _ in 0..runs.max(1) {
        let start = Instant::now();
        let built = build::build(scene, skeleton, hydro)?;
        let field = CarvedTerrain::new(built);
        builds.push(start.elapsed().as_secs_f64());
        model = Some(field);
    }
    let field = model.expect("at least one run");
    let dir = scratch_dir(Path::new(&format!("sdf-{}", scene.name)));
    std::fs::create_dir_all(&dir).map_err(|e| StageError::failure(format!("{}: {e}", dir.display())))?;
    let run = karst_artifact::cli::StageRun::new(Stage::Sdf, &dir);
    let header =
        karst_artifact::write_artifact(&dir.join("sdf.bin"), &run.provenance("bench"), field.model())?;
    let _ = std::fs::remove_dir_all(&dir);

    let [uniform, near] = karst_sdf::synthetic::eval_points(&field, skeleton, 200_000);
    let time = |points: &[DVec3]| {
        let (mut wall, mut cpu) = (Vec::new(), Vec::new());
        for _ in 0..runs.max(1) {
            let (start, cpu_start) = (Instant::now(), cpu_seconds());
            let sum: f64 = points.iter().map(|&p| field.eval(p)).sum();
            std::hint::black_box(sum);
            wall.push(start.elapsed().as_secs_f64() * 1e9 / points.len() as f64);
            cpu.extend(cpu_seconds().zip(cpu_start).map(|(e, s)| (e - s) * 1e9 / points.len() as f64));
        }
        (median(wall), (!cpu.is_empty()).then(|| median(cpu)))
    };
    let by_kind: Vec<(&'static str, usize)> = field.model().primitive_counts().into_iter().collect();
    let primitives = by_kind.iter().filter(|(k, _)| *k != "water").map(|(_, n)| n).sum();
    let (eval_uniform_ns, eval_uniform_cpu_ns) = time(&uniform);
    let (eval_near_ns, eval_near_cpu_ns) = time(&near);
    Ok(SdfBench {
        primitives,
        by_kind,
        build_seconds: median(builds),
        eval_uniform_ns,
        eval_near_ns,
        eval_uniform_cpu_ns,
        eval_near_cpu_ns,
        memory_bytes: field.memory(),
        artifact_bytes: header.payload_len,
    })
}

/// The mesher's budget case (issue 8): a seeded synthetic model of about 30k capsules in a
/// 1 × 1 × 0.4 km³ domain, as in Paris et al. 2021 §7.5, presets being not yet available.
pub mod synthetic {
    use std::time::Instant;

    use glam::DVec3;
    use karst_geology::Domain;
    use karst_geology::rng::Random;
    use karst_mesher::Surface;
    use karst_mesher::polygonize::polygonize;
    use karst_mesher::volume::{Cave, Volume};
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

    fn time(name: &str, runs: usize, mesh: impl Fn() -> Surface) -> Case {
        let mut seconds = Vec::new();
        let mut cpu = Vec::new();
        let mut surface = Surface::default();
        reset_peak_memory();
        for _ in 0..runs.max(1) {
            drop(std::mem::take(&mut surface));
            let (start, cpu_start) = (Instant::now(), super::cpu_seconds());
            surface = mesh();
            seconds.push(start.elapsed().as_secs_f64());
            cpu.extend(super::cpu_seconds().zip(cpu_start).map(|(end, start)| end - start));
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
    fn mesh_hash(surface: &Surface) -> u64 {
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
}

/// Timing of karst-metrics (and karstnet, when available) on one network.
#[derive(Debug, Clone)]
pub struct NetworkTiming {
    pub name: String,
    pub nodes: usize,
    pub reduced_nodes: usize,
    /// Median seconds of `characterize`.
    pub ours: f64,
    /// karstnet's seconds for load + `characterize_graph()` + the extra metrics, timed inside
    /// Python (start-up and imports excluded; `None` without `KARSTNET_PYTHON`).
    pub karstnet: Option<f64>,
}

/// Times `characterize` on Sakany and Monachou (from `fixtures/caves`) and on
/// generated networks of about 7,000 and 10,000 nodes; karstnet too when `KARSTNET_PYTHON` is set.
pub fn time_networks(runs: usize) -> Result<Vec<NetworkTiming>, StageError> {
    let caves = Path::new("fixtures/caves");
    let scratch = scratch_dir(Path::new("networks"));
    std::fs::create_dir_all(&scratch)
        .map_err(|e| StageError::failure(format!("{}: {e}", scratch.display())))?;
    let mut cases: Vec<(String, Network, PathBuf)> = Vec::new();
    if let Ok(net) = readers::read_karstnet(&caves.join("Sakany")) {
        cases.push(("Sakany".into(), net, caves.join("Sakany")));
    }
    if let Ok(net) = readers::read_pline(&caves.join("Monachou.pl")) {
        cases.push(("Monachou".into(), net, caves.join("Monachou.pl")));
    }
    for (name, tree_nodes) in [("generated-7k", 6_400), ("generated-10k", 9_200)] {
        let net = generated_network(7, tree_nodes);
        let base = scratch.join(name);
        write_karstnet(&net, &base).map_err(|e| StageError::failure(format!("{}: {e}", base.display())))?;
        cases.push((name.into(), net, base));
    }
    let python = std::env::var("KARSTNET_PYTHON").ok();
    let mut timings = Vec::new();
    for (name, net, file) in cases {
        let metrics = characterize(&net).map_err(|e| StageError::input(format!("{name}: {e}")))?;
        let ours = median(
            (0..runs.max(1))
                .map(|_| {
                    let start = Instant::now();
                    let _ = characterize(&net);
                    start.elapsed().as_secs_f64()
                })
                .collect(),
        );
        let karstnet = python.as_deref().and_then(|p| karstnet_seconds(p, &file));
        timings.push(NetworkTiming {
            name,
            nodes: metrics.n_nodes_full,
            reduced_nodes: metrics.n_nodes_simpl,
            ours,
            karstnet,
        });
    }
    let _ = std::fs::remove_dir_all(&scratch);
    Ok(timings)
}

/// karstnet's own time on `file` (load and metrics), as `karstnet_oracle.py` reports it.
fn karstnet_seconds(python: &str, file: &Path) -> Option<f64> {
    let script = Path::new("crates/metrics/tests/karstnet_oracle.py");
    let out = std::process::Command::new(python).arg(script).arg(file).output().ok()?;
    let stderr = String::from_utf8_lossy(&out.stderr);
    let line = stderr.lines().find_map(|l| l.strip_prefix("karstnet seconds: "))?;
    out.status.success().then(|| line.trim().parse().ok()).flatten()
}

/// A cave-like network: a random walk tree with long chains (each new station continues the
/// previous one with probability 0.9), plus loops closed between random stations.
fn generated_network(seed: u64, tree_nodes: usize) -> Network {
    let mut state = seed;
    let mut next = move || {
        state = state.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = state;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        ((z ^ (z >> 31)) >> 11) as f64 / (1u64 << 53) as f64
    };
    let mut nodes = vec![[0.0; 3]];
    let mut links = Vec::new();
    for i in 1..tree_nodes {
        let parent = if next() < 0.9 { i - 1 } else { (next() * i as f64) as usize };
        let p = nodes[parent];
        nodes.push([p[0] + 10.0 * (next() - 0.5), p[1] + 10.0 * (next() - 0.5), p[2] + 2.0 * (next() - 0.5)]);
        links.push([parent, i]);
    }
    for _ in 0..tree_nodes / 25 {
        let (a, b) = ((next() * tree_nodes as f64) as usize, (next() * tree_nodes as f64) as usize);
        if a == b {
            continue;
        }
        let stations = (next() * 5.0) as usize;
        let mut previous = a;
        for k in 1..=stations {
            let t = k as f64 / (stations + 1) as f64;
            let (pa, pb) = (nodes[a], nodes[b]);
            nodes.push([0, 1, 2].map(|c| pa[c] + (pb[c] - pa[c]) * t + (next() - 0.5)));
            links.push([previous, nodes.len() - 1]);
            previous = nodes.len() - 1;
        }
        links.push([previous, b]);
    }
    Network { nodes, links }
}

/// karstnet's `{base}_nodes.dat` and `{base}_links.dat` (1-based links).
fn write_karstnet(net: &Network, base: &Path) -> std::io::Result<()> {
    let mut nodes = String::new();
    for [x, y, z] in &net.nodes {
        nodes += &format!("{x} {y} {z}\n");
    }
    let mut links = String::new();
    for [a, b] in &net.links {
        links += &format!("{} {}\n", a + 1, b + 1);
    }
    let name = base.file_name().map(|n| n.to_string_lossy().into_owned()).unwrap_or_default();
    std::fs::write(base.with_file_name(format!("{name}_nodes.dat")), nodes)?;
    std::fs::write(base.with_file_name(format!("{name}_links.dat")), links)
}
