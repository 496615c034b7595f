//! `cargo xtask`: run the pipeline, diff and bless artifacts, benchmark, test.

use std::path::{Path, PathBuf};
use std::process::{Command, ExitCode};

use clap::{Parser, Subcommand};

use karst_artifact::{Stage, StageError};
use karst_geology::Scene;
use xtask::executor::{Binaries, InProcess};
use xtask::pipeline::{self, Selection};
use xtask::tools::Tools;
use xtask::{bench, diff, ensemble, metrics_table};

/// The embedded default scene, run when `cargo xtask run` is given no scene.
const DEFAULT_SCENE: &str = include_str!("../../fixtures/scenes/default.toml");
/// The data files the default scene names, written beside it (paths relative to the scene).
const DEFAULT_DATA: &[(&str, &[u8])] = &[
    ("data/plateau.png", include_bytes!("../../fixtures/scenes/data/plateau.png")),
    ("data/marl-parting.ts", include_bytes!("../../fixtures/scenes/data/marl-parting.ts")),
];
/// The scene whose artifacts are pinned in `fixtures/golden/tiny`.
const GOLDEN_SCENE: &str = "fixtures/scenes/tiny.toml";
const GOLDEN_DIR: &str = "fixtures/golden/tiny";
/// Scenes timed by `cargo xtask bench`.
const BENCH_SCENES: &[&str] = &["fixtures/scenes/tiny.toml", "fixtures/scenes/default.toml"];
/// Scenes whose sampling alone `cargo xtask bench` times (issue 3's budgets).
const SAMPLING_BENCH_SCENES: &[&str] =
    &["fixtures/bench/sampling-100k.toml", "fixtures/bench/sampling-1m.toml"];

/// Cost-graph budget cases (issue 4), on random points in the default scene's domain.
const COSTGRAPH_CASES: &[bench::CostgraphCase] =
    &[bench::CostgraphCase { samples: 100_000, k: 50 }, bench::CostgraphCase { samples: 1_000_000, k: 30 }];

#[derive(Parser)]
#[command(name = "cargo xtask", about = "karstgen's task runner")]
struct Cli {
    #[command(subcommand)]
    command: Task,
}

#[derive(Subcommand)]
enum Task {
    /// Run the pipeline on SCENE (default: the embedded default scene), skipping up-to-date stages.
    Run {
        /// Scene file; without it, the embedded default scene runs into out/default.
        scene: Option<PathBuf>,
        /// Output folder (default out/<scene name>).
        #[arg(long)]
        out: Option<PathBuf>,
        /// Rerun this stage and every later one.
        #[arg(long, value_parser = parse_stage)]
        from: Option<Stage>,
        /// Run only this stage.
        #[arg(long, value_parser = parse_stage, conflicts_with = "from")]
        only: Option<Stage>,
        /// Rerun every stage.
        #[arg(long)]
        force: bool,
    },
    /// Compare two artifacts of the same kind; exit 1 when they differ beyond tolerance.
    Diff {
        a: PathBuf,
        b: PathBuf,
        /// Relative tolerance on numbers.
        #[arg(long, default_value_t = 1e-9)]
        tol: f64,
    },
    /// Regenerate the golden artifacts of the tiny scene and print what changed.
    Bless,
    /// Time every stage of the benchmark scenes (median of RUNS runs).
    Bench {
        #[arg(long, default_value_t = 5)]
        runs: usize,
        /// Only the cost-graph budget cases (100k samples at k = 50, 1M at k = 30).
        #[arg(long)]
        costgraph: bool,
        /// Only the sdf budgets (synthetic network and looping preset).
        #[arg(long, conflicts_with = "costgraph")]
        sdf: bool,
        /// Only the mesher's synthetic budget cases (issue 8).
        #[arg(long, conflicts_with_all = ["costgraph", "sdf"])]
        mesher: bool,
        /// Only the GeoTIFF terrain budget (a 4000 × 4000 float32 LZW raster).
        #[arg(long, conflicts_with_all = ["costgraph", "sdf", "mesher"])]
        geotiff: bool,
    },
    /// Run N seeds of SCENE in parallel: every realization's metrics in one CSV, their summary and
    /// the conduit probability grid (EXR slices and a top-view PNG).
    Ensemble {
        scene: PathBuf,
        /// Number of realizations (seeds scene seed .. scene seed + N − 1).
        #[arg(long, default_value_t = 50)]
        n: usize,
        /// Edge of a probability-grid cell, metres.
        #[arg(long, default_value_t = 10.0)]
        cell: f64,
        /// Output folder (default out/ensemble-<scene name>).
        #[arg(long)]
        out: Option<PathBuf>,
    },
    /// Table karstnet's metrics of every fixtures/scenes/*.toml against the real-cave ranges.
    MetricsTable {
        /// Also copy each metrics.json to fixtures/metrics/ and update the README's table.
        #[arg(long)]
        write: bool,
    },
    /// Run the test suite (`cargo test --release --workspace`), after installing the outside
    /// tools the tests check outputs with (tools/: Python packages, Debian packages, npm).
    Test {
        /// Extra arguments for cargo test.
        #[arg(trailing_var_arg = true, allow_hyphen_values = true)]
        args: Vec<String>,
    },
}

fn parse_stage(name: &str) -> Result<Stage, String> {
    Stage::from_name(name).ok_or_else(|| {
        let names: Vec<&str> = Stage::ALL.iter().map(|s| s.name()).collect();
        format!("unknown stage \"{name}\"; stages: {}", names.join(", "))
    })
}

fn main() -> ExitCode {
    let root = workspace_root();
    if let Err(e) = std::env::set_current_dir(&root) {
        eprintln!("error: cannot enter the workspace {}: {e}", root.display());
        return ExitCode::from(1);
    }
    let result = match Cli::parse().command {
        Task::Run { scene, out, from, only, force } => run(scene, out, Selection { from, only, force }),
        Task::Diff { a, b, tol } => return diff_command(&a, &b, tol),
        Task::Bless => bless(),
        Task::Bench { runs, costgraph, sdf, mesher, geotiff } => {
            if geotiff {
                geotiff_bench(runs)
            } else {
                bench_command(runs, costgraph, sdf, mesher)
            }
        }
        Task::Test { args } => return test(&args),
        Task::Ensemble { scene, n, cell, out } => ensemble_command(scene, n, cell, out),
        Task::MetricsTable { write } => metrics_table_command(write),
    };
    karst_artifact::cli::finish(result)
}

fn workspace_root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).parent().expect("xtask lives in the workspace").to_path_buf()
}

fn run(scene: Option<PathBuf>, out: Option<PathBuf>, selection: Selection) -> Result<(), StageError> {
    let (scene_path, out) = match scene {
        Some(path) => {
            let parsed = Scene::load(&path)?;
            let out = out.unwrap_or_else(|| pipeline::default_out(&parsed));
            (path, out)
        }
        None => {
            let out = out.unwrap_or_else(|| PathBuf::from("out/default"));
            let path = out.join("scene.toml");
            for (file, bytes) in DEFAULT_DATA {
                write_if_changed(&out.join(file), bytes)?;
            }
            write_if_changed(&path, DEFAULT_SCENE.as_bytes())?;
            (path, out)
        }
    };
    let binaries = Binaries::build().map_err(StageError::Failure)?;
    println!("scene {} → {}", scene_path.display(), out.display());
    pipeline::run(&scene_path, &out, &selection, &binaries, true)?;
    Ok(())
}

fn write_if_changed(path: &Path, bytes: &[u8]) -> Result<(), StageError> {
    if std::fs::read(path).ok().as_deref() == Some(bytes) {
        return Ok(());
    }
    if let Some(folder) = path.parent() {
        std::fs::create_dir_all(folder)
            .map_err(|e| StageError::failure(format!("{}: cannot create: {e}", folder.display())))?;
    }
    karst_artifact::atomic::write_bytes(path, bytes)
        .map_err(|e| StageError::failure(format!("{}: cannot write: {e}", path.display())))
}

fn diff_command(a: &Path, b: &Path, tol: f64) -> ExitCode {
    match diff::diff(a, b, tol) {
        Ok(report) => {
            let verdict = if report.differs() { "differ" } else { "match" };
            println!("{} vs {}: {} artifacts {verdict}", a.display(), b.display(), report.kind.name());
            print!("{}", report.summary());
            ExitCode::from(u8::from(report.differs()))
        }
        Err(e) => karst_artifact::cli::finish(Err(e)),
    }
}

fn bless() -> Result<(), StageError> {
    let scratch = std::env::temp_dir().join(format!("karstgen-bless-{}", std::process::id()));
    let selection = Selection { force: true, ..Selection::default() };
    pipeline::run(Path::new(GOLDEN_SCENE), &scratch, &selection, &InProcess, false)?;
    let golden = Path::new(GOLDEN_DIR);
    std::fs::create_dir_all(golden).map_err(|e| StageError::failure(format!("{}: {e}", golden.display())))?;
    for stage in Stage::ALL {
        let (new, old) = (scratch.join(stage.file_name()), golden.join(stage.file_name()));
        match diff::diff(&old, &new, 1e-9) {
            Ok(report) if !report.differs() => println!("{}: unchanged", stage.file_name()),
            Ok(report) => println!("{}: changed\n{}", stage.file_name(), report.summary()),
            Err(e) => println!("{}: replaced ({e})", stage.file_name()),
        }
        std::fs::copy(&new, &old).map_err(|e| StageError::failure(format!("{}: {e}", old.display())))?;
    }
    let _ = std::fs::remove_dir_all(&scratch);
    Ok(())
}

/// Conduits of the synthetic sdf benchmark network (about 30k primitives).
const SDF_BENCH_CONDUITS: usize = 100;

fn bench_command(
    runs: usize,
    costgraph_only: bool,
    sdf_only: bool,
    mesher_only: bool,
) -> Result<(), StageError> {
    println!("median of {runs} runs, in process, release build, {} threads", rayon_threads());
    if mesher_only {
        mesher_bench(runs);
        return Ok(());
    }
    if sdf_only {
        return sdf_bench(runs);
    }
    let scenes = if costgraph_only { &[][..] } else { BENCH_SCENES };
    for scene in scenes {
        println!("\n{scene}");
        println!("{:<10} {:>10}", "stage", "seconds");
        for (stage, seconds) in bench::time_scene(Path::new(scene), runs)? {
            println!("{:<10} {seconds:>10.4}", stage.name());
        }
    }
    let sampling_scenes = if costgraph_only { &[][..] } else { SAMPLING_BENCH_SCENES };
    for scene in sampling_scenes {
        let (seconds, headline) = bench::time_stage(Path::new(scene), Stage::Sampling, runs)?;
        println!("\n{scene}\nsampling {seconds:>10.4} s: {headline}");
    }

    println!("\ncostgraph build on uniform random points in the default scene's domain");
    println!(
        "{:>9} {:>4} {:>10} {:>10} {:>11} {:>8} {:>10}",
        "samples", "k", "seconds", "CPU s", "edges", "B/edge", "peak MB"
    );
    for case in COSTGRAPH_CASES {
        let t = bench::time_costgraph(Path::new("fixtures/scenes/default.toml"), case, runs)?;
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
    for (case, samples, seconds) in bench::time_skeleton_budgets(runs)? {
        println!("{case:<45} {samples:>7} samples {seconds:>8.4} s");
    }

    sdf_bench(runs)?;
    mesher_and_network_bench(runs)?;
    geotiff_bench(runs)
}

/// The GeoTIFF terrain budget (issue 16).
fn geotiff_bench(runs: usize) -> Result<(), StageError> {
    let t = xtask::geodata_bench::time_geotiff_terrain(runs)?;
    let mb = |b: u64| format!("{:.0}", b as f64 / 1e6);
    let side = xtask::geodata_bench::SIDE;
    println!(
        "
GeoTIFF terrain: {side} × {side} float32 LZW ({} MB file), Scene::load",
        mb(t.file_bytes)
    );
    println!(
        "{:.3} s, CPU {} s, peak memory {} MB above the process's (the raster's own float32 size: {} MB)",
        t.seconds,
        t.cpu_seconds.map_or("-".into(), |c| format!("{c:.2}")),
        t.peak_above.map_or("-".into(), mb),
        mb(side as u64 * side as u64 * 4)
    );
    Ok(())
}

/// The mesher's budget cases (issue 8) on a synthetic model of 30k capsules.
fn mesher_bench(runs: usize) {
    println!("\nmesher, synthetic 30k capsules (issue 8)");
    for case in bench::synthetic::run(runs) {
        let cpu = case.cpu_seconds.map_or("-".into(), |c| format!("{c:.2}"));
        println!(
            "{:<45} {:>8.3} s  CPU {cpu:>6} s  {:>10} triangles  {:>5.2} evaluations/vertex  peak {:.0} MB  mesh {:016x}",
            case.name, case.seconds, case.triangles, case.evaluations_per_vertex, case.peak_mb, case.hash
        );
    }
}

/// The sdf budgets (issue 7) on a synthetic network of about 30k primitives and on the
/// looping preset's tree.
fn sdf_bench(runs: usize) -> Result<(), StageError> {
    let synthetic = bench::sdf_network(SDF_BENCH_CONDUITS, runs)?;
    print_sdf_bench(&format!("synthetic network of {SDF_BENCH_CONDUITS} conduits"), &synthetic);
    let looping = bench::sdf_preset(Path::new("fixtures/scenes/looping.toml"), runs)?;
    print_sdf_bench("looping preset", &looping);
    Ok(())
}

fn print_sdf_bench(name: &str, b: &bench::SdfBench) {
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
    mesher_bench(runs);

    println!("\nnetwork statistics (karstnet: load and metrics, Python start-up excluded)");
    println!(
        "{:<14} {:>7} {:>8} {:>12} {:>12} {:>8}",
        "network", "nodes", "reduced", "karstgen s", "karstnet s", "ratio"
    );
    for t in bench::time_networks(runs)? {
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

fn ensemble_command(scene: PathBuf, n: usize, cell: f64, out: Option<PathBuf>) -> Result<(), StageError> {
    let name = Scene::load(&scene)?.name;
    let out = out.unwrap_or_else(|| PathBuf::from("out").join(format!("ensemble-{name}")));
    println!("{}", ensemble::run(&ensemble::EnsembleArgs { scene, n, cell, out })?);
    Ok(())
}

fn metrics_table_command(write: bool) -> Result<(), StageError> {
    let mut reports = Vec::new();
    let scenes = metrics_table::scenes(Path::new("fixtures/scenes"))?;
    let bar = karst_artifact::progress::bar(scenes.len() as u64, "scenes");
    for scene in scenes {
        let name = scene.file_stem().map(|s| s.to_string_lossy().into_owned()).unwrap_or_default();
        let out = PathBuf::from("out/metrics-table").join(&name);
        reports.push((name, metrics_table::scene_report(&scene, &out)?));
        bar.inc(1);
    }
    bar.finish_and_clear();
    let table = metrics_table::markdown(&reports);
    print!("{table}");
    if write {
        let fail = |p: &Path, e: std::io::Error| StageError::failure(format!("{}: {e}", p.display()));
        let dir = Path::new("fixtures/metrics");
        std::fs::create_dir_all(dir).map_err(|e| fail(dir, e))?;
        for (name, _) in &reports {
            let target = dir.join(format!("{name}.json"));
            let source = PathBuf::from("out/metrics-table").join(name).join("metrics.json");
            std::fs::copy(&source, &target).map_err(|e| fail(&target, e))?;
        }
        let readme = Path::new("README.md");
        let text = std::fs::read_to_string(readme).map_err(|e| fail(readme, e))?;
        write_if_changed(readme, metrics_table::replace_section(&text, &table).as_bytes())?;
    }
    Ok(())
}

fn rayon_threads() -> usize {
    std::thread::available_parallelism().map(|n| n.get()).unwrap_or(1)
}

fn test(args: &[String]) -> ExitCode {
    let tools = match Tools::ensure(&workspace_root()) {
        Ok(tools) => tools,
        Err(e) => {
            eprintln!("error: cannot install the test tools: {e}");
            return ExitCode::from(1);
        }
    };
    let cargo = std::env::var_os("CARGO").unwrap_or_else(|| "cargo".into());
    let status =
        Command::new(cargo).args(["test", "--release", "--workspace"]).args(args).envs(tools.env()).status();
    match status {
        Ok(s) if s.success() => ExitCode::SUCCESS,
        Ok(_) => ExitCode::from(1),
        Err(e) => {
            eprintln!("error: cannot run cargo test: {e}");
            ExitCode::from(1)
        }
    }
}
