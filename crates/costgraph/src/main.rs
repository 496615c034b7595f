//! `karst-costgraph`: stage 2 of karstgen. `run SCENE --out DIR` writes DIR/costgraph.bin;
//! `inspect FILE [--json]` prints a summary or the whole artifact.

use std::process::ExitCode;

use clap::Parser;
use karst_costgraph::CostgraphStage;
use karst_stage::cli::{self, InspectArgs, RunArgs, default_sigpipe, finish};

/// k-nearest-neighbour graph with geology-driven edge costs (karstgen stage 2).
#[derive(Parser)]
#[command(name = "karst-costgraph", version)]
enum Cli {
    /// Build the cost graph of DIR/samples.bin into DIR/costgraph.bin.
    Run(RunArgs),
    /// Summarize a costgraph artifact (or print it whole with --json).
    Inspect(InspectArgs),
}

fn main() -> ExitCode {
    default_sigpipe();
    finish(match Cli::parse() {
        Cli::Run(args) => cli::run::<CostgraphStage>(&args),
        Cli::Inspect(args) => cli::inspect::<CostgraphStage>(&args),
    })
}
