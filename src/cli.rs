//! The command line: its arguments and what each command does.

use std::path::{Path, PathBuf};
use std::process::ExitCode;

use clap::{Parser, Subcommand};

use karst_artifact::StageId;
use karst_pipeline::budget::OutputBudget;
use karst_pipeline::make::{self, Selection};
use karst_pipeline::scene::{self, SceneFile};
use karst_pipeline::{calibrate, diff, ensemble, registry, verdict};
use karst_stage::StageError;
use karst_stage::cli::{default_sigpipe, finish};

/// Geologically coherent 3D karst cave networks and their cave geometry.
#[derive(Parser)]
#[command(name = "karstgen", version)]
pub struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand)]
enum Command {
    /// Run the pipeline on SCENE (default: the embedded default scene), skipping up-to-date stages.
    Run(RunArgs),
    /// Summarize any artifact (samples.bin … metrics.json), or print it whole with --json.
    Inspect(karst_stage::cli::InspectArgs),
    /// Compare two artifacts of the same kind; exit 1 when they differ beyond tolerance.
    Diff(DiffArgs),
    /// karstnet's statistics of any network file (karstnet .dat, GOCAD PLine or CSV), as JSON.
    Metrics(MetricsArgs),
    /// Many seeds of SCENE in parallel (resumable), or `merge` ensemble folders: every
    /// realization's metrics and hydro figures, their summary and the conduit probability.
    Ensemble(EnsembleArgs),
    /// Search the network parameters of SCENE's [calibrate] box that bring its networks closest
    /// to a surveyed cave, yours (--target) or a published one (--like; --like list names them),
    /// by CMA-ES over karstnet's statistics.
    Calibrate(CalibrateArgs),
    /// Write a run's outputs in other tools' formats (VTK, GOCAD, Survex, SWMM, glTF, OBJ, PLY,
    /// CSV) into DIR/export/.
    Export(karst_export::stage::ExportArgs),
    /// Write the web viewer of a run into DIR/view/ (and serve it on 127.0.0.1 with --serve).
    View(karst_view::cli::ViewArgs),
    /// Draw a picture of an output.
    #[command(subcommand)]
    Render(Render),
}

/// `karstgen run`.
#[derive(Debug, Clone, clap::Args)]
pub struct RunArgs {
    /// Scene file; without it, the embedded default scene runs into out/default.
    pub scene: Option<PathBuf>,
    /// Output folder (default out/<scene name>, under the working folder).
    #[arg(long)]
    pub out: Option<PathBuf>,
    /// Rerun this stage and every later one.
    #[arg(long, value_parser = parse_stage)]
    pub from: Option<StageId>,
    /// Run only this stage.
    #[arg(long, value_parser = parse_stage, conflicts_with = "from")]
    pub only: Option<StageId>,
    /// Stop after this stage.
    #[arg(long, value_parser = parse_stage)]
    pub to: Option<StageId>,
    /// Rerun every stage.
    #[arg(long)]
    pub force: bool,
    /// Memory the stages may plan to use (e.g. 16G, 512M; default 16G); a stage whose work
    /// estimate is above it refuses, naming the scene field to change (docs/limits.md).
    #[arg(long, value_name = "SIZE")]
    pub max_memory: Option<karst_scene::budget::Budget>,
    /// MB the meshes may take (default 300): the mesher's work is estimated before it runs,
    /// and a run above this stops, naming the fields that lower it.
    #[arg(long, value_name = "MB")]
    pub budget: Option<OutputBudget>,
}

/// `karstgen diff`.
#[derive(Debug, Clone, clap::Args)]
pub struct DiffArgs {
    pub a: PathBuf,
    pub b: PathBuf,
    /// Relative tolerance on numbers.
    #[arg(long, default_value_t = 1e-9)]
    pub tol: f64,
}

/// `karstgen metrics`.
#[derive(Debug, Clone, clap::Args)]
pub struct MetricsArgs {
    #[command(flatten)]
    network: karst_metrics::stage::NetworkFile,
    /// Also write the plots of the network (PNG) into this folder.
    #[arg(long, value_name = "DIR")]
    plots: Option<PathBuf>,
}

/// `karstgen ensemble`: run realizations, or merge ensemble folders.
#[derive(Debug, Clone, clap::Args)]
#[command(args_conflicts_with_subcommands = true, subcommand_negates_reqs = true)]
pub struct EnsembleArgs {
    #[command(subcommand)]
    merge: Option<EnsembleMerge>,
    #[command(flatten)]
    run: EnsembleRunArgs,
}

#[derive(Debug, Clone, Subcommand)]
enum EnsembleMerge {
    /// Gather ensemble folders of one scene and settings (e.g. seed ranges run on several
    /// machines) into one, and summarise it.
    Merge {
        /// Ensemble folders to merge.
        #[arg(required = true)]
        dirs: Vec<PathBuf>,
        /// The merged folder (may be one of DIRS).
        #[arg(long)]
        out: PathBuf,
        /// probability.tif counts conduits within this depth band only: MIN..MAX metres below
        /// ground [default: any depth].
        #[arg(long, value_parser = ensemble::parse_depth_band)]
        depth_band: Option<[f64; 2]>,
    },
}

/// `karstgen ensemble SCENE`.
#[derive(Debug, Clone, clap::Args)]
struct EnsembleRunArgs {
    #[arg(required = true)]
    scene: Option<PathBuf>,
    /// Number of realizations: seeds scene seed .. scene seed + N − 1 [default: 50].
    #[arg(long, conflicts_with = "seeds")]
    n: Option<usize>,
    /// Seeds to run: a range 100..200 (end excluded), 100..=199, a list 1,5,7, or a mix.
    #[arg(long)]
    seeds: Option<String>,
    /// Run each realization to this stage and the stages it needs, or `all` [default: hydro,
    /// what the metrics read].
    #[arg(long, value_parser = parse_to)]
    to: Option<ToStage>,
    /// Edge of a probability-grid cell, metres.
    #[arg(long, default_value_t = ensemble::DEFAULT_CELL)]
    cell: f64,
    /// Artifacts each realization keeps beside its record: stage names separated by commas,
    /// `all` (the whole folder) or `none`.
    #[arg(long, default_value = "none", value_parser = ensemble::Keep::parse)]
    keep: ensemble::Keep,
    /// probability.tif counts conduits within this depth band only: MIN..MAX metres below
    /// ground [default: any depth].
    #[arg(long, value_parser = ensemble::parse_depth_band)]
    depth_band: Option<[f64; 2]>,
    /// Output folder (default out/ensemble-<scene name>). A rerun into it skips the complete
    /// realizations.
    #[arg(long)]
    out: Option<PathBuf>,
}

/// `karstgen calibrate`.
#[derive(Debug, Clone, clap::Args)]
#[command(group = clap::ArgGroup::new("aim").required(false).args(["target", "like"]))]
pub struct CalibrateArgs {
    /// The scene, with a [calibrate] box (not needed by `--like list`).
    scene: Option<PathBuf>,
    /// The surveyed cave: karstnet's BASE_nodes.dat (or BASE), a GOCAD PLine .pl, or two CSV
    /// files NODES EDGES. Without --target or --like: the one the scene's [calibrate] names.
    #[arg(long, num_args = 1..=2, value_name = "CAVE")]
    target: Vec<PathBuf>,
    /// A published network (KNdata-public, any case), `surveyed` for the median of its 25
    /// surveyed caves, or `list` to print the names.
    #[arg(long, value_name = "NAME")]
    like: Option<String>,
    /// Output folder (default out/calibrate-<scene name>).
    #[arg(long)]
    out: Option<PathBuf>,
}

/// `--to`: a stage, or every stage.
#[derive(Debug, Clone, Copy)]
struct ToStage(Option<StageId>);

fn parse_to(name: &str) -> Result<ToStage, String> {
    if name == "all" { Ok(ToStage(None)) } else { parse_stage(name).map(|s| ToStage(Some(s))) }
}

/// `karstgen render`.
#[derive(Subcommand)]
enum Render {
    /// The network of a skeleton artifact: top and side views, conduits coloured by type.
    Skeleton(karst_skeleton::stage::RenderArgs),
    /// A run's network coloured by water type (top and side views).
    Hydro(karst_hydro::stage::RenderArgs),
    /// The map of a run's surface streams over the scene's terrain, coloured by water type.
    Streams(karst_streams::stage::RenderArgs),
    /// One surface of a mesh artifact, shaded.
    Mesh(karst_mesher::stage::RenderArgs),
    /// A horizontal (--z) or vertical (--y, --x) slice of an sdf artifact, as PNG and/or EXR.
    Slice(karst_sdf::stage::SliceArgs),
    /// The cross-section library (one section per conduit type).
    Sections(karst_sdf::stage::SectionsArgs),
}

fn parse_stage(name: &str) -> Result<StageId, String> {
    StageId::from_name(name).ok_or_else(|| {
        let names: Vec<&str> = StageId::ALL.iter().map(|s| s.name()).collect();
        format!("unknown stage \"{name}\"; stages: {}", names.join(", "))
    })
}

/// The `karstgen` process: parses the command line, runs the command, returns the exit code.
pub fn main() -> ExitCode {
    default_sigpipe();
    match Cli::parse().command {
        Command::Diff(args) => diff_command(&args),
        command => finish(execute(command)),
    }
}

fn execute(command: Command) -> Result<(), StageError> {
    match command {
        Command::Run(args) => run(&args).map(|_| ()),
        Command::Inspect(args) if args.json => registry::print_json(&args.file),
        Command::Inspect(args) => {
            registry::inspect(&args.file)?.iter().for_each(|line| println!("{line}"));
            Ok(())
        }
        Command::Metrics(args) => {
            karst_metrics::stage::characterize_file(&args.network, args.plots.as_deref())
        }
        Command::Ensemble(args) => ensemble_command(args),
        Command::Calibrate(args) => calibrate_command(args),
        Command::Export(args) => karst_export::stage::export_run(&args),
        Command::View(args) => karst_view::cli::view(&args),
        Command::Render(render) => match render {
            Render::Skeleton(args) => karst_skeleton::stage::render(&args),
            Render::Hydro(args) => karst_hydro::stage::render(&args),
            Render::Streams(args) => karst_streams::stage::render(&args),
            Render::Mesh(args) => karst_mesher::stage::render(&args),
            Render::Slice(args) => karst_sdf::stage::slice(&args),
            Render::Sections(args) => karst_sdf::stage::sections(&args),
        },
        Command::Diff(_) => unreachable!("diff has its own exit codes"),
    }
}

/// `karstgen run`: prints the scene and output folder, then a line per stage; returns the
/// output folder.
pub fn run(args: &RunArgs) -> Result<PathBuf, StageError> {
    let (scene, out) = match &args.scene {
        Some(path) => {
            let scene = SceneFile::load(path)?;
            let out = args.out.clone().unwrap_or_else(|| scene::default_out(&scene.scene));
            (scene, out)
        }
        None => {
            let out = args.out.clone().unwrap_or_else(|| PathBuf::from("out").join(scene::DEFAULT_NAME));
            (SceneFile::default_in(&out)?, out)
        }
    };
    let mut scene = scene;
    if let Some(budget) = args.max_memory {
        scene.scene.set_budget(budget);
    }
    println!("scene {} → {}", scene.path.display(), out.display());
    let selection = Selection {
        from: args.from,
        only: args.only,
        to: args.to,
        force: args.force,
        budget: args.budget.unwrap_or_default(),
    };
    let reports = make::run(&scene, &out, &selection, &mut |report| println!("{}", report.line()))?;
    verdict::verdict(&out, &reports)?.iter().for_each(|line| println!("{line}"));
    Ok(out)
}

/// `karstgen diff`: prints the comparison; exit code 0 when the artifacts match, 1 when they
/// differ, 2 when one cannot be read.
pub fn diff_command(args: &DiffArgs) -> ExitCode {
    match diff::diff(&args.a, &args.b, args.tol) {
        Ok(report) => {
            let verdict = if report.differs() { "differ" } else { "match" };
            println!(
                "{} vs {}: {} artifacts {verdict}",
                args.a.display(),
                args.b.display(),
                report.kind.row().kind
            );
            print!("{}", report.summary());
            ExitCode::from(u8::from(report.differs()))
        }
        Err(e) => finish(Err(e)),
    }
}

fn ensemble_command(args: EnsembleArgs) -> Result<(), StageError> {
    if let Some(EnsembleMerge::Merge { dirs, out, depth_band }) = args.merge {
        println!("{}", ensemble::merge(&dirs, &out, depth_band)?.line(&out));
        return Ok(());
    }
    let run = args.run;
    let scene = SceneFile::load(run.scene.as_deref().unwrap_or(Path::new("")))?;
    let seeds = match &run.seeds {
        Some(spec) => ensemble::parse_seeds(spec),
        None => ensemble::first_n(scene.scene.seed(), run.n.unwrap_or(50)),
    }
    .map_err(|e| StageError::input(format!("ensemble: {e}")))?;
    let out =
        run.out.unwrap_or_else(|| PathBuf::from("out").join(format!("ensemble-{}", scene.scene.name())));
    let to = run.to.map_or(Some(ensemble::DEFAULT_TO), |t| t.0);
    let plan = ensemble::Plan::new(scene, to, run.cell, run.keep)?;
    println!("{}", ensemble::run(&plan, &out, &seeds, run.depth_band)?.line(&out));
    Ok(())
}

fn calibrate_command(args: CalibrateArgs) -> Result<(), StageError> {
    let target = match args.like {
        Some(name) if name.eq_ignore_ascii_case("list") => {
            calibrate::like_names()?.iter().for_each(|line| println!("{line}"));
            return Ok(());
        }
        Some(name) => Some(calibrate::Aim::Like(name)),
        None if args.target.is_empty() => None,
        None => Some(calibrate::Aim::Cave(args.target)),
    };
    let scene = args.scene.ok_or_else(|| StageError::input("calibrate: give the SCENE to calibrate"))?;
    let name = SceneFile::load(&scene)?.scene.name().to_string();
    let out = args.out.unwrap_or_else(|| PathBuf::from("out").join(format!("calibrate-{name}")));
    let summary = calibrate::run(&calibrate::CalibrateArgs { scene, target, out })?;
    println!("{summary}");
    Ok(())
}

/// `path` made absolute against `base` (the user's working folder) when relative.
pub fn resolve(base: &Path, path: &Path) -> PathBuf {
    if path.is_absolute() { path.to_path_buf() } else { base.join(path) }
}

#[cfg(test)]
mod tests {
    use clap::Parser;
    use clap::error::ErrorKind;

    use super::Cli;

    fn refused(args: &[&str]) -> clap::Error {
        match Cli::try_parse_from(args) {
            Ok(_) => panic!("{args:?} accepted"),
            Err(e) => e,
        }
    }

    #[test]
    fn calibrate_takes_like_or_target_not_both() {
        let both = refused(&["karstgen", "calibrate", "s.toml", "--like", "Sakany", "--target", "c.pl"]);
        assert_eq!(both.kind(), ErrorKind::ArgumentConflict);
        assert_eq!(both.exit_code(), 2);
        assert!(both.to_string().contains("--like"), "{both}");
        // Neither: the scene's `[calibrate]` must name one (checked when the scene is read).
        assert!(Cli::try_parse_from(["karstgen", "calibrate", "s.toml"]).is_ok());
        assert!(Cli::try_parse_from(["karstgen", "calibrate", "s.toml", "--like", "surveyed"]).is_ok());
        assert!(Cli::try_parse_from(["karstgen", "calibrate", "--like", "list"]).is_ok());
    }

    #[test]
    fn like_without_a_scene_exits_2() {
        let Ok(cli) = Cli::try_parse_from(["karstgen", "calibrate", "--like", "Sakany"]) else { panic!() };
        let e = super::execute(cli.command).unwrap_err();
        assert_eq!(e.exit_code(), 2);
        assert!(e.to_string().contains("SCENE"), "{e}");
    }
}
