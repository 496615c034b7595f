//! `karst-hydro`: stage 4 of karstgen. `run SCENE --out DIR` writes DIR/hydro.json;
//! `inspect FILE [--json]` prints a summary or the whole artifact.

use std::process::ExitCode;

use clap::Parser;
use karst_artifact::cli::{InspectArgs, RunArgs, finish};
use karst_hydro::stage;

/// Poisson-disk sampling of the bedrock (karstgen stage 4).
#[derive(Parser)]
#[command(name = "karst-hydro", version)]
enum Cli {
    /// Compute the flows of DIR/skeleton.json into DIR/hydro.json.
    Run(RunArgs),
    /// Summarize a hydro artifact (or print it whole with --json).
    Inspect(InspectArgs),
}

fn main() -> ExitCode {
    finish(match Cli::parse() {
        Cli::Run(args) => stage::run(&args).map(|headline| println!("{headline}")),
        Cli::Inspect(args) => stage::inspect(&args),
    })
}
