//! `cargo xtask`: the developers' tasks. `run`, `diff` and `inspect` are `karstgen`'s own (the
//! same code); `bless` diffs the tiny scene against the golden artifacts (and replaces them with
//! `--accept --why`), `bench` times every stage, `test` installs the test tools and runs the
//! suite, `metrics-table` tables every scene's metrics, `fuzz` runs the fuzz targets for a while,
//! `modules` checks that no crate has an import circle,
//! `ensemble` the presets' metrics over many seeds.

use std::path::{Path, PathBuf};
use std::process::{Command, ExitCode};

use clap::{Parser, Subcommand};

use karst_pipeline::scene;
use karst_stage::StageError;
use karst_stage::cli::finish;
use xtask::tools::Tools;
use xtask::{bench, metrics_table};

/// The scene whose artifacts are pinned in `fixtures/golden/tiny`.

#[derive(Parser)]
#[command(name = "cargo xtask", about = "karstgen's developer tasks")]
struct Cli {
    #[command(subcommand)]
    command: Task,
}

#[derive(Subcommand)]
enum Task {
    /// `karstgen run`: the pipeline on SCENE (default: the embedded default scene).
    Run(karstgen::cli::RunArgs),
    /// `karstgen diff`: compare two artifacts of the same kind; exit 1 when they differ.
    Diff(karstgen::cli::DiffArgs),
    /// `karstgen view`: write (and serve) the web viewer of a run.
    View(karst_view::cli::ViewArgs),
    /// The tiny scene's artifacts diffed against the goldens; with --accept --why, replace them
    /// and record why in fixtures/golden/CHANGES.md.
    Bless {
        /// Replace the goldens (nothing is written without it).
        #[arg(long, requires = "why")]
        accept: bool,
        /// Why the new artifacts are right, recorded in fixtures/golden/CHANGES.md.
        #[arg(long, value_name = "REASON", value_parser = clap::builder::NonEmptyStringValueParser::new())]
        why: Option<String>,
    },
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
        /// Only the mesher's synthetic budget cases.
        #[arg(long, conflicts_with_all = ["costgraph", "sdf"])]
        mesher: bool,
        /// With --mesher: only the cases whose name contains this text (e.g. "streamed").
        #[arg(long, value_name = "TEXT", requires = "mesher")]
        case: Option<String>,
        /// Only the streams budgets (surface network, pipeline overhead, carved terrain).
        #[arg(long, conflicts_with_all = ["costgraph", "sdf", "mesher"])]
        streams: bool,
        /// Only the GeoTIFF terrain budget (a 4000 × 4000 float32 LZW raster).
        #[arg(long, conflicts_with_all = ["costgraph", "sdf", "mesher", "export", "streams"])]
        geotiff: bool,
        /// Only the export formats, on the finished run in this folder (e.g. out/looping).
        #[arg(long, value_name = "DIR", conflicts_with_all = ["costgraph", "sdf", "mesher", "streams"])]
        export: Option<PathBuf>,
        /// Only the network half beside KarstNSim (pykarstnsim in .venv-peer), alternating runs.
        #[arg(long, conflicts_with_all = ["costgraph", "sdf", "mesher", "streams", "export"])]
        peer: bool,
        /// Only the regional scene (fixtures/bench/regional.toml): the network half at about 1 M
        /// and 5 M samples, then the other stages but the export at 5 M (takes tens of minutes).
        #[arg(long, conflicts_with_all = ["costgraph", "sdf", "mesher", "streams", "export", "peer", "geotiff", "mazes", "calibrate"])]
        regional: bool,
        /// With --regional: the network half only.
        #[arg(long, requires = "regional")]
        network: bool,
        /// Only the network statistics of mazes (grids of 40k and 250k nodes).
        #[arg(long, conflicts_with_all = ["costgraph", "sdf", "mesher", "export", "peer"])]
        mazes: bool,
        /// Only the calibration budgets: the default scene's [calibrate] box to the Sakany cave, the
        /// surveyed median and two published caves, each re-run on three fresh seeds.
        #[arg(long, conflicts_with_all = ["costgraph", "sdf", "mesher", "export", "peer", "mazes"])]
        calibrate: bool,
    },
    /// Table karstnet's metrics of every fixtures/scenes/*.toml against the real-cave ranges.
    MetricsTable {
        /// Also copy each metrics.json to fixtures/metrics/ and update the README's table.
        #[arg(long)]
        write: bool,
    },
    /// Fuzz every reader (scene, artifacts, network and data files) for MINUTES with new
    /// seeds; each failure is shrunk and saved in fixtures/bad/fuzz/ (exit 1 when any).
    Fuzz {
        #[arg(long, default_value_t = 10.0)]
        minutes: f64,
        /// First random seed (later rounds take the next ones).
        #[arg(long, default_value_t = 1)]
        seed: u64,
    },
    /// The network's defaults on a generated population of scenes (no `[skeleton]`): share of
    /// realizations inside the real-cave ranges, on the tuning and the held-out scene seeds.
    RealismDefaults {
        /// Also replace the table in docs/metrics.md.
        #[arg(long)]
        write: bool,
        /// Only the tuning set.
        #[arg(long)]
        tuning: bool,
        /// Only the first 12 scenes of the tuning set, one seed each (to iterate on a rule).
        #[arg(long, conflicts_with = "write")]
        quick: bool,
    },
    /// Table the presets' metrics over N seeds each (`karstgen ensemble`) against the real-cave
    /// ranges: median, 10th–90th percentile, share inside.
    Ensemble {
        /// Realizations per preset.
        #[arg(long, default_value_t = 20)]
        n: usize,
        /// Also replace the table in docs/metrics.md.
        #[arg(long)]
        write: bool,
    },
    /// Check that no crate of the workspace has an import circle (modules reaching each other
    /// through `crate::` paths); exit 1 when one has.
    Modules,
    /// Run the test suite (`cargo test --release --workspace`, then the Python package's
    /// pytest suite), after installing the outside tools the tests check outputs with
    /// (tools/: Python packages, Debian packages, npm).
    Test {
        /// Only the Python package: build and install its wheel, run pytest.
        #[arg(long)]
        python: bool,
        /// Extra arguments for cargo test (then the Python suite does not run).
        #[arg(trailing_var_arg = true, allow_hyphen_values = true)]
        args: Vec<String>,
    },
}

fn main() -> ExitCode {
    // Paths given by the user are relative to where they ran `cargo xtask`; the tasks' own
    // paths (fixtures/, out/) to the workspace.
    let cli = Cli::parse();
    let here = std::env::current_dir().unwrap_or_default();
    let root = workspace_root();
    if let Err(e) = std::env::set_current_dir(&root) {
        eprintln!("error: cannot enter the workspace {}: {e}", root.display());
        return ExitCode::from(1);
    }
    let result = match cli.command {
        Task::Run(mut args) => {
            args.scene = args.scene.map(|p| karstgen::cli::resolve(&here, &p));
            args.out = args.out.map(|p| karstgen::cli::resolve(&here, &p));
            karstgen::cli::run(&args).map(|_| ())
        }
        Task::Diff(args) => {
            let (a, b) = (karstgen::cli::resolve(&here, &args.a), karstgen::cli::resolve(&here, &args.b));
            return karstgen::cli::diff_command(&karstgen::cli::DiffArgs { a, b, tol: args.tol });
        }
        Task::View(mut args) => {
            args.dir = karstgen::cli::resolve(&here, &args.dir);
            args.scene = args.scene.map(|p| karstgen::cli::resolve(&here, &p));
            karst_view::cli::view(&args)
        }
        Task::Bless { accept, why } => xtask::bless::bless(why.as_deref().filter(|_| accept)),
        Task::Bench { runs, peer: true, .. } => peer_bench(runs),
        Task::Bench { regional: true, network, .. } => regional_bench(!network),
        Task::Bench {
            runs,
            costgraph,
            sdf,
            mesher,
            case,
            streams,
            geotiff,
            export,
            calibrate,
            mazes,
            ..
        } => bench::run(
            runs,
            bench::Only {
                costgraph,
                sdf,
                mesher,
                mesher_case: case,
                streams,
                geotiff,
                export,
                calibrate,
                mazes,
            },
        ),
        Task::Test { python, args } => return test(python, &args),
        Task::Modules => return modules(&root),
        Task::Fuzz { minutes, seed } => fuzz(minutes, seed),
        Task::MetricsTable { write } => metrics_table_command(write),
        Task::Ensemble { n, write } => ensemble_table_command(n, write),
        Task::RealismDefaults { write, tuning, quick } => realism_command(write, tuning, quick),
    };
    finish(result)
}

/// `cargo xtask fuzz`: every target in turn, 500 cases a round, until the time is up.
fn fuzz(minutes: f64, seed: u64) -> Result<(), StageError> {
    let root = workspace_root();
    let failures = karst_fuzz::run_for(minutes * 60.0, 500, seed);
    for failure in &failures {
        let saved = karst_fuzz::save(&root, failure)
            .map_err(|e| StageError::failure(format!("cannot save a regression case: {e}")))?;
        eprintln!("{failure}\n  saved as {}", saved.display());
    }
    if failures.is_empty() {
        println!("fuzz: {minutes} min, no failure");
        Ok(())
    } else {
        Err(StageError::failure(format!(
            "fuzz: {} failure(s), saved in fixtures/bad/fuzz/: fix the readers, keep the files",
            failures.len()
        )))
    }
}

/// karstgen's network half beside KarstNSim on `peer::SCENE` (issue 21), every case.
fn peer_bench(runs: usize) -> Result<(), StageError> {
    use xtask::peer;
    let python = peer::peer_python(&workspace_root())?;
    let karstgen = peer::karstgen_binary()?;
    println!("{} vs KarstNSim (pykarstnsim 2.0.1), {runs} alternating runs each, medians", peer::SCENE);
    println!(
        "| case | samples (ours / theirs) | KarstNSim wall / CPU / peak | karstgen wall / CPU / peak | ratio wall / CPU | load |"
    );
    println!("|---|---|---|---|---|---|");
    for case in peer::CASES {
        let load = peer::load_average();
        let r = peer::run_case(case, runs, &karstgen, &python)?;
        let (ours, theirs) = r.medians();
        let show = |u: peer::Usage| {
            format!("{:.2} s / {:.2} s / {:.0} MB", u.wall, u.cpu, u.peak_bytes as f64 / 1e6)
        };
        let load = match (load, peer::load_average()) {
            (Some(a), Some(b)) => format!("{a:.1}–{b:.1}"),
            _ => "-".into(),
        };
        println!(
            "| {} | {} / {} | {} | {} | {:.1}× / {:.1}× | {load} |",
            case.name,
            r.our_samples,
            r.their_samples,
            show(theirs),
            show(ours),
            theirs.wall / ours.wall,
            theirs.cpu / ours.cpu
        );
    }
    Ok(())
}

/// Every stage on the regional scene (issue 21), once; the table for BENCHMARKS.md.
fn regional_bench(full: bool) -> Result<(), StageError> {
    use xtask::{peer, regional};
    let binaries = regional::binaries()?;
    let before = peer::load_average();
    let (small, large) = regional::run(&binaries, full)?;
    let load = match (before, peer::load_average()) {
        (Some(a), Some(b)) => format!("load average {a:.1} before, {b:.1} after"),
        _ => "load average unknown".into(),
    };
    println!("{} (each stage once, as its own process; {load})", regional::SCENE);
    print!("{}", regional::table(&small, &large));
    Ok(())
}

fn workspace_root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).parent().expect("xtask lives in the workspace").to_path_buf()
}

fn metrics_table_command(write: bool) -> Result<(), StageError> {
    let mut reports = Vec::new();
    let scenes = metrics_table::scenes(Path::new("fixtures/scenes"))?;
    let bar = karst_stage::progress::bar(scenes.len() as u64, "scenes");
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
        scene::write_if_changed(readme, metrics_table::replace_section(&text, &table).as_bytes())?;
    }
    Ok(())
}

fn ensemble_table_command(n: usize, write: bool) -> Result<(), StageError> {
    use xtask::ensemble_table::{self, BEGIN, END, PRESETS};
    let mut sets = Vec::new();
    for preset in PRESETS {
        eprintln!("{preset}: {n} realizations");
        sets.push(ensemble_table::realize(preset, n)?);
    }
    let table = ensemble_table::markdown(&sets);
    print!("{table}");
    if write {
        write_into_metrics_doc(BEGIN, END, &table)?;
    }
    Ok(())
}

/// Puts `table` between the markers `begin` and `end` of docs/metrics.md (written only if it
/// changes).
fn write_into_metrics_doc(begin: &str, end: &str, table: &str) -> Result<(), StageError> {
    let doc = Path::new("docs/metrics.md");
    let text =
        std::fs::read_to_string(doc).map_err(|e| StageError::failure(format!("{}: {e}", doc.display())))?;
    let updated = metrics_table::replace_between(&text, begin, end, table);
    scene::write_if_changed(doc, updated.as_bytes())
}

/// `cargo xtask realism-defaults`: both sets (or the tuning set, or its quick subset), the table
/// printed and, with `--write`, put into docs/metrics.md.
fn realism_command(write: bool, tuning_only: bool, quick: bool) -> Result<(), StageError> {
    use xtask::realism::{self, BEGIN, END, Set, Subset};
    let sets: &[Set] = if tuning_only || quick { &[Set::Tuning] } else { &[Set::Tuning, Set::HeldOut] };
    let subset = if quick { Subset::QUICK } else { Subset::FULL };
    let mut results = Vec::new();
    for &set in sets {
        results.push((set, realism::run_set(set, subset, &realism::out_dir())?));
    }
    let table = realism::markdown(&results, subset);
    print!("{table}");
    if write {
        write_into_metrics_doc(BEGIN, END, &table)?;
    }
    Ok(())
}

/// The tests run again in the `checked` profile (release with integer overflow checks and debug
/// assertions, which cost too much to keep in release: BENCHMARKS.md, "Overflow checks"): the
/// tiny scene through every stage against its goldens, and the presets' networks.
const CHECKED_SUBSET: [&str; 6] = ["-p", "karstgen-tests", "--test", "golden", "--test", "presets"];

/// `cargo test --profile checked` of [`CHECKED_SUBSET`].
fn checked_subset(tools: &Tools) -> Result<(), String> {
    let cargo = std::env::var_os("CARGO").unwrap_or_else(|| "cargo".into());
    let status = Command::new(cargo)
        .args(["test", "--profile", "checked"])
        .args(CHECKED_SUBSET)
        .envs(tools.env())
        .status()
        .map_err(|e| format!("cannot run cargo test: {e}"))?;
    if status.success() { Ok(()) } else { Err("the checked subset failed".into()) }
}

fn test(python_only: bool, args: &[String]) -> ExitCode {
    let root = workspace_root();
    let tools = match Tools::ensure(&root) {
        Ok(tools) => tools,
        Err(e) => {
            eprintln!("error: cannot install the test tools: {e}");
            return ExitCode::from(1);
        }
    };
    if !python_only {
        // The Python package's crate has no Rust tests: its tests are pytest, run below.
        let cargo = std::env::var_os("CARGO").unwrap_or_else(|| "cargo".into());
        let status = Command::new(cargo)
            .args(["test", "--release", "--workspace", "--exclude", "karstgen-python"])
            .args(args)
            .envs(tools.env())
            .status();
        match status {
            Ok(s) if s.success() => {}
            Ok(_) => return ExitCode::from(1),
            Err(e) => {
                eprintln!("error: cannot run cargo test: {e}");
                return ExitCode::from(1);
            }
        }
        if !args.is_empty() {
            return ExitCode::SUCCESS;
        }
        if let Err(e) = checked_subset(&tools) {
            eprintln!("error: {e}");
            return ExitCode::from(1);
        }
    }
    match xtask::python::test(&root, &tools) {
        Ok(true) => ExitCode::SUCCESS,
        Ok(false) => ExitCode::from(1),
        Err(e) => {
            eprintln!("error: the Python package: {e}");
            ExitCode::from(1)
        }
    }
}

/// `cargo xtask modules`: prints every circle; exit 1 when any, 2 when a source cannot be read.
fn modules(root: &Path) -> ExitCode {
    match xtask::modules::check_workspace(root) {
        Ok(circles) if circles.is_empty() => {
            println!("no import circle in any crate");
            ExitCode::SUCCESS
        }
        Ok(circles) => {
            for circle in &circles {
                print!("{circle}");
            }
            println!("{} import circles", circles.len());
            ExitCode::from(1)
        }
        Err(e) => {
            eprintln!("error: {e}");
            ExitCode::from(2)
        }
    }
}
