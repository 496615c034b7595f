//! `cargo xtask bench`: times every stage of the benchmark scenes in process (median of several
//! runs per stage), then each stage's budget cases, one file per stage, and the network
//! statistics beside karstnet 1.2.5 when `KARSTNET_PYTHON` names its interpreter.

use std::path::{Path, PathBuf};

use karst_artifact::StageId;
use karst_stage::StageError;

use crate::temp_folder::TempFolder;

mod calibrate;
mod costgraph;
mod export;
mod geotiff;
mod mesher;
mod metrics;
mod pipeline;
mod probes;
mod sdf;
mod skeleton;
mod streams;

/// Scenes timed stage by stage.
const BENCH_SCENES: &[&str] = &["fixtures/scenes/tiny.toml", "fixtures/scenes/default.toml"];
/// Scenes whose sampling alone is timed.
const SAMPLING_BENCH_SCENES: &[&str] =
    &["fixtures/bench/sampling-100k.toml", "fixtures/bench/sampling-1m.toml"];

/// Cost-graph budget cases, on random points in the default scene's domain.
const COSTGRAPH_CASES: &[costgraph::CostgraphCase] = &[
    costgraph::CostgraphCase { samples: 100_000, k: 50 },
    costgraph::CostgraphCase { samples: 1_000_000, k: 30 },
];

/// Conduits of the synthetic sdf benchmark network (about 30k primitives).
const SDF_BENCH_CONDUITS: usize = 100;

/// Scenes whose surface network is timed: the budget's and the waterfall preset.
const STREAMS_SCENES: &[&str] = &["fixtures/scenes/default.toml", "fixtures/scenes/waterfall.toml"];
/// The scene whose pipeline the streams must not slow by more than 10 %.
const STREAMS_PIPELINE_SCENE: &str = "fixtures/scenes/default.toml";
/// The preset whose carved terrain is meshed with and without its streams, and the cell.
const CARVING_SCENE: &str = "fixtures/scenes/waterfall.toml";
const CARVING_CELL: f64 = 1.0;

/// Which benchmarks to run.
#[derive(Debug, Clone, Default)]
pub struct Only {
    pub costgraph: bool,
    pub sdf: bool,
    pub mesher: bool,
    /// Only the mesher cases whose name contains this text.
    pub mesher_case: Option<String>,
    pub streams: bool,
    pub geotiff: bool,
    /// The export formats on the finished run in this folder.
    pub export: Option<PathBuf>,
    pub mazes: bool,
    /// The calibration budget (default scene to the Sakany cave).
    pub calibrate: bool,
}

/// `cargo xtask bench`: runs the benchmarks and prints their tables.
pub fn run(runs: usize, only: Only) -> Result<(), StageError> {
    let Only {
        costgraph: costgraph_only,
        sdf: sdf_only,
        mesher: mesher_only,
        mesher_case,
        streams: streams_only,
        geotiff: geotiff_only,
        export,
        calibrate,
        mazes,
    } = only;
    if calibrate {
        println!("one run, in process, release build, {} threads", rayon_threads());
        return calibrate::calibrate_bench();
    }
    println!("median of {runs} runs, in process, release build, {} threads", rayon_threads());
    if mazes {
        return maze_bench(runs);
    }
    if let Some(dir) = export {
        return export_bench(&dir, runs);
    }
    if streams_only {
        return streams_bench(runs);
    }
    if geotiff_only {
        return geotiff_bench(runs);
    }
    if mesher_only {
        return mesher_bench(runs, mesher_case.as_deref());
    }
    if sdf_only {
        return sdf_bench(runs);
    }
    let scenes = if costgraph_only { &[][..] } else { BENCH_SCENES };
    for scene in scenes {
        println!("\n{scene}");
        println!("{:<10} {:>10}", "stage", "seconds");
        for (stage, seconds) in pipeline::time_scene(Path::new(scene), runs)? {
            println!("{:<10} {seconds:>10.4}", stage.name());
        }
    }
    let sampling_scenes = if costgraph_only { &[][..] } else { SAMPLING_BENCH_SCENES };
    for scene in sampling_scenes {
        let (seconds, headline) = pipeline::time_stage(Path::new(scene), StageId::Sampling, runs)?;
        println!("\n{scene}\nsampling {seconds:>10.4} s: {headline}");
    }

    println!("\ncostgraph build on uniform random points in the default scene's domain");
    println!(
        "{:>9} {:>4} {:>10} {:>10} {:>11} {:>8} {:>10}",
        "samples", "k", "seconds", "CPU s", "edges", "B/edge", "peak MB"
    );
    for case in COSTGRAPH_CASES {
        let t = costgraph::time_costgraph(Path::new("fixtures/scenes/default.toml"), case, runs)?;
        let peak = t.peak_bytes.map_or("-".into(), |b| format!("{:.0}", b as f64 / 1e6));
        let cpu = t.cpu_seconds.map_or("-".into(), |c| format!("{c:.2}"));
        println!(
            "{:>9} {:>4} {:>10.4} {cpu:>10} {:>11} {:>8.1} {peak:>10}",
            case.samples, case.k, t.seconds, t.edges, t.bytes_per_edge
        );
    }

    if costgraph_only {
        return Ok(());
    }
    println!("\nskeleton budgets (paths only, sampling and cost graph excluded)");
    for (case, samples, seconds) in skeleton::time_skeleton_budgets(runs)? {
        println!("{case:<45} {samples:>7} samples {seconds:>8.4} s");
    }

    sdf_bench(runs)?;
    streams_bench(runs)?;
    mesher_and_network_bench(runs)?;
    geotiff_bench(runs)
}

/// The GeoTIFF terrain budget: loading a scene over a large raster.
fn geotiff_bench(runs: usize) -> Result<(), StageError> {
    let t = geotiff::time_geotiff_terrain(runs)?;
    let mb = |b: u64| format!("{:.0}", b as f64 / 1e6);
    let side = geotiff::SIDE;
    println!("\nGeoTIFF terrain: {side} × {side} float32 LZW ({} MB file), Scene::load", mb(t.file_bytes));
    println!(
        "{:.3} s, CPU {} s, peak memory {} MB above the process's (the raster's own float32 size: {} MB)",
        t.seconds,
        t.cpu_seconds.map_or("-".into(), |c| format!("{c:.2}")),
        t.peak_above.map_or("-".into(), mb),
        mb(side as u64 * side as u64 * 4)
    );
    Ok(())
}

/// The streams budgets: the surface network per scene, the default pipeline's overhead, the
/// carved terrain's evaluations per vertex.
fn streams_bench(runs: usize) -> Result<(), StageError> {
    println!("\nsurface network and classification (streams stage build; budget 50 ms on default)");
    for scene in STREAMS_SCENES {
        let t = streams::time_network(Path::new(scene), runs)?;
        let cpu = t.cpu_seconds.map_or("-".into(), |c| format!("{:.1}", c * 1e3));
        println!("{scene:<32} {:>8.1} ms  (CPU {cpu} ms per build)  {}", t.seconds * 1e3, t.headline);
    }
    let o = streams::overhead(Path::new(STREAMS_PIPELINE_SCENE), runs)?;
    let extra = o.streams_seconds + o.sdf_extra + o.mesher_extra;
    println!(
        "\n{STREAMS_PIPELINE_SCENE}: pipeline {:.3} s, of which the streams add {:.4} s ({:+.1} % on the {:.3} s without them; budget +10 %): \
         streams {:.4} s, sdf {:+.4} s, mesher {:+.4} s (paired, mesher alone {:.3} s)",
        o.pipeline_seconds,
        extra,
        100.0 * extra / (o.pipeline_seconds - extra),
        o.pipeline_seconds - extra,
        o.streams_seconds,
        o.sdf_extra,
        o.mesher_extra,
        o.mesher_without
    );
    if let (Some(extra), Some(without)) = (o.cpu_extra, o.cpu_without) {
        println!(
            "  sdf + mesher in CPU time, paired: {without:.2} s without the streams, {extra:+.3} s with them ({:+.1} %)",
            100.0 * extra / without
        );
    }
    let c = streams::carving(Path::new(CARVING_SCENE), CARVING_CELL)?;
    println!(
        "{CARVING_SCENE} terrain at {CARVING_CELL} m: {:.2} field evaluations per vertex carved, {:.2} uncarved ({} and {} triangles)",
        c.evaluations_per_vertex[0], c.evaluations_per_vertex[1], c.triangles[0], c.triangles[1]
    );
    Ok(())
}

/// The mesher's budget cases  on a synthetic model of 30k capsules per km², those whose name
/// contains `only` (all when None).
fn mesher_bench(runs: usize, only: Option<&str>) -> Result<(), StageError> {
    println!("\nmesher, synthetic 30k capsules per km²");
    for case in mesher::run(runs, only)? {
        let cpu = case.cpu_seconds.map_or("-".into(), |c| format!("{c:.2}"));
        println!(
            "{:<45} {:>8.3} s  CPU {cpu:>6} s  {:>10} triangles  {:>5.2} evaluations/vertex  peak {:.0} MB  mesh {:016x}",
            case.name, case.seconds, case.triangles, case.evaluations_per_vertex, case.peak_mb, case.hash
        );
    }
    Ok(())
}

/// The sdf budgets  on a synthetic network of about 30k primitives and on the
/// looping preset's tree.
fn sdf_bench(runs: usize) -> Result<(), StageError> {
    let synthetic = sdf::sdf_network(SDF_BENCH_CONDUITS, runs)?;
    print_sdf_bench(&format!("synthetic network of {SDF_BENCH_CONDUITS} conduits"), &synthetic);
    let looping = sdf::sdf_preset(Path::new("fixtures/scenes/looping.toml"), runs)?;
    print_sdf_bench("looping preset", &looping);
    Ok(())
}

fn print_sdf_bench(name: &str, b: &sdf::SdfBench) {
    let kinds: Vec<String> = b.by_kind.iter().map(|(k, n)| format!("{n} {k}")).collect();
    println!("\nsdf, {name}: {} primitives ({})", b.primitives, kinds.join(", "));
    println!("build + BVH        {:>10.4} s", b.build_seconds);
    let cpu = |c: Option<f64>| c.map_or(String::new(), |c| format!(" ({c:.0} ns CPU)"));
    println!("eval, uniform      {:>10.1} ns per point{}", b.eval_uniform_ns, cpu(b.eval_uniform_cpu_ns));
    println!("eval, near conduits{:>10.1} ns per point{}", b.eval_near_ns, cpu(b.eval_near_cpu_ns));
    let per = |bytes: f64| bytes / b.primitives.max(1) as f64;
    let [karst, water] = b.memory_bytes;
    println!("memory, karst      {karst:>10} bytes ({:.1} per primitive)", per(karst as f64));
    println!("memory, water      {water:>10} bytes ({:.1} per primitive)", per(water as f64));
    println!(
        "memory, both       {:>10} bytes ({:.1} per primitive)",
        karst + water,
        per((karst + water) as f64)
    );
    println!(
        "artifact payload   {:>10} bytes ({:.1} per primitive)",
        b.artifact_bytes,
        per(b.artifact_bytes as f64)
    );
}

fn mesher_and_network_bench(runs: usize) -> Result<(), StageError> {
    mesher_bench(runs, None)?;

    println!("\nnetwork statistics (karstnet: load and metrics, Python start-up excluded)");
    println!(
        "{:<14} {:>7} {:>8} {:>12} {:>12} {:>8}",
        "network", "nodes", "reduced", "karstgen s", "karstnet s", "ratio"
    );
    for t in metrics::time_networks(runs)? {
        let (theirs, ratio) = match t.karstnet {
            Some(k) => (format!("{k:.3}"), format!("{:.0}x", k / t.ours)),
            None => ("(set KARSTNET_PYTHON)".into(), String::new()),
        };
        println!(
            "{:<14} {:>7} {:>8} {:>12.4} {theirs:>12} {ratio:>8}",
            t.name, t.nodes, t.reduced_nodes, t.ours
        );
    }
    Ok(())
}

/// The network statistics of mazes, where the all-pairs traversals dominate; each row is
/// printed as soon as it is measured (the 250,000-junction grid takes minutes).
fn maze_bench(runs: usize) -> Result<(), StageError> {
    println!("\nnetwork statistics of mazes");
    println!("{:<16} {:>8} {:>8} {:>12}", "network", "nodes", "reduced", "karstgen s");
    for (name, net) in metrics::mazes() {
        let t = metrics::time_maze(name, &net, runs)?;
        println!("{:<16} {:>8} {:>8} {:>12.3}", t.name, t.nodes, t.reduced_nodes, t.ours);
        std::io::Write::flush(&mut std::io::stdout())
            .map_err(|e| StageError::failure(format!("stdout: {e}")))?;
    }
    Ok(())
}

fn rayon_threads() -> usize {
    std::thread::available_parallelism().map(|n| n.get()).unwrap_or(1)
}

fn median(mut values: Vec<f64>) -> f64 {
    values.sort_by(f64::total_cmp);
    values[values.len() / 2]
}

/// The scratch folder of a bench on `scene` (or of a name), removed when dropped.
fn scratch_dir(scene: &Path) -> TempFolder {
    let name = scene.file_stem().map(|s| s.to_string_lossy().into_owned()).unwrap_or_default();
    TempFolder::new(&format!("bench-{name}"))
}

fn export_bench(dir: &Path, runs: usize) -> Result<(), StageError> {
    println!("exports of {}, median of {runs} runs", dir.display());
    println!("{:<14} {:>10} {:>14}", "formats", "seconds", "bytes");
    for t in export::time_exports(dir, runs)? {
        println!("{:<14} {:>10.3} {:>14}", t.case, t.seconds, t.bytes);
    }
    Ok(())
}
