//! `karst-metrics`: stage 8 of karstgen, and karstnet's statistics for any network.
//!
//! - `run SCENE --out DIR` writes DIR/metrics.json from DIR/skeleton.json, hydro.json and streams.json;
//! - `inspect FILE [--json]` prints a summary or the whole artifact;
//! - `--karstnet BASE`, `--pline FILE.pl`, `--csv NODES EDGES` print the metrics of a surveyed or
//!   simulated network as JSON, with karstnet's key names, each `characterize_graph()` metric
//!   beside its real-cave range; `--plots DIR` also draws the rose diagram, the branch-length
//!   histogram and the range chart there.

use std::path::PathBuf;
use std::process::ExitCode;

use clap::{Parser, Subcommand};
use karst_metrics::MetricsStage;
use karst_metrics::stage::{NetworkFile, characterize_file};
use karst_stage::cli::{self, InspectArgs, RunArgs, default_sigpipe, finish};

/// Karst network statistics identical to karstnet 1.2.5 (karstgen stage 8).
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
    /// Compute the statistics of DIR/skeleton.json (with its water and the surface streams) into DIR/metrics.json.
    Run(RunArgs),
    /// Summarize a metrics artifact (or print it whole with --json).
    Inspect(InspectArgs),
}

fn main() -> ExitCode {
    default_sigpipe();
    let cli = Cli::parse();
    finish(match cli.command {
        Some(Command::Run(args)) => cli::run::<MetricsStage>(&args),
        Some(Command::Inspect(args)) => cli::inspect::<MetricsStage>(&args),
        None => characterize_file(&cli.network, cli.plots.as_deref()),
    })
}
