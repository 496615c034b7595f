//! `karst-metrics`: stage 7 of karstgen, and karstnet's statistics for any network.
//!
//! - `run SCENE --out DIR` writes DIR/metrics.json from DIR/skeleton.json;
//! - `inspect FILE [--json]` prints a summary or the whole artifact;
//! - `--karstnet BASE`, `--pline FILE.pl`, `--csv NODES EDGES` print the metrics of a surveyed or
//!   simulated network as JSON, with karstnet's key names, each `characterize_graph()` metric
//!   beside its real-cave range; `--plots DIR` also draws the rose diagram, the branch-length
//!   histogram and the range chart there.

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use std::process::ExitCode;

use clap::{Args, Parser, Subcommand};
use karst_artifact::StageError;
use karst_artifact::cli::{InspectArgs, RunArgs, default_sigpipe, finish};
use karst_metrics::ranges::{self, Compared};
use karst_metrics::{Metrics, Network, ReadError, characterize, readers, stage};
use serde::Serialize;

/// Karst network statistics identical to karstnet 1.2.5 (karstgen stage 7).
#[derive(Parser)]
#[command(name = "karst-metrics", version, args_conflicts_with_subcommands = true)]
struct Cli {
    #[command(subcommand)]
    command: Option<Command>,
    #[command(flatten)]
    network: NetworkFile,
    /// Also write the plots of the network (PNG) into this folder.
    #[arg(long, value_name = "DIR")]
    plots: Option<PathBuf>,
}

#[derive(Subcommand)]
enum Command {
    /// Compute the statistics of DIR/skeleton.json into DIR/metrics.json.
    Run(RunArgs),
    /// Summarize a metrics artifact (or print it whole with --json).
    Inspect(InspectArgs),
}

/// A network file to characterize.
#[derive(Args)]
#[group(multiple = false)]
struct NetworkFile {
    /// karstnet's BASE_nodes.dat and BASE_links.dat (BASE, or either file's name).
    #[arg(long, value_name = "BASE")]
    karstnet: Option<PathBuf>,
    /// A GOCAD PLine file.
    #[arg(long, value_name = "FILE.pl")]
    pline: Option<PathBuf>,
    /// CSV node table (id,x,y[,z]) and edge table (from,to | from_id,to_id | source,target),
    /// delimited by `,` or `;`.
    #[arg(long, num_args = 2, value_names = ["NODES", "EDGES"])]
    csv: Option<Vec<PathBuf>>,
}

fn main() -> ExitCode {
    default_sigpipe();
    let cli = Cli::parse();
    finish(match cli.command {
        Some(Command::Run(args)) => stage::run(&args).map(|headline| println!("{headline}")),
        Some(Command::Inspect(args)) => stage::inspect(&args),
        None => characterize_file(&cli.network, cli.plots.as_deref()),
    })
}

/// What the command prints for a network file.
#[derive(Serialize)]
struct FileReport<'a> {
    karstnet: BTreeMap<&'a str, Compared>,
    network: &'a Metrics,
}

fn characterize_file(file: &NetworkFile, plots: Option<&Path>) -> Result<(), StageError> {
    let (network, name) = read(file)?;
    let metrics = characterize(&network).map_err(|e| StageError::input(format!("{name}: {e}")))?;
    let report = FileReport { karstnet: ranges::compare(&metrics).into_iter().collect(), network: &metrics };
    let text = serde_json::to_string_pretty(&report).map_err(|e| StageError::failure(e.to_string()))?;
    println!("{text}");
    if let Some(dir) = plots {
        stage::write_plots(dir, &network, &metrics)?;
    }
    Ok(())
}

fn read(file: &NetworkFile) -> Result<(Network, String), StageError> {
    let bad = |e: ReadError| StageError::input(e.to_string());
    let show = |p: &Path| p.display().to_string();
    if let Some(base) = &file.karstnet {
        return Ok((readers::read_karstnet(base).map_err(bad)?, show(base)));
    }
    if let Some(path) = &file.pline {
        return Ok((readers::read_pline(path).map_err(bad)?, show(path)));
    }
    if let Some([nodes, edges]) = file.csv.as_deref() {
        return Ok((readers::read_csv(nodes, edges).map_err(bad)?, show(nodes)));
    }
    Err(StageError::input(
        "give a subcommand (run, inspect) or a network: --karstnet BASE, --pline FILE.pl or --csv NODES EDGES",
    ))
}
