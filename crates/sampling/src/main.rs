//! `karst-sampling`: stage 1 of karstgen. `run SCENE --out DIR` writes DIR/samples.bin;
//! `inspect FILE [--json]` prints a summary or the whole artifact.

use std::process::ExitCode;

use clap::Parser;
use karst_sampling::SamplingStage;
use karst_stage::cli::{self, InspectArgs, RunArgs, default_sigpipe, finish};

/// Poisson-disk sampling of the bedrock (karstgen stage 1).
#[derive(Parser)]
#[command(name = "karst-sampling", version)]
enum Cli {
    /// Sample the scene's bedrock into DIR/samples.bin.
    Run(RunArgs),
    /// Summarize a samples artifact (or print it whole with --json).
    Inspect(InspectArgs),
}

fn main() -> ExitCode {
    default_sigpipe();
    finish(match Cli::parse() {
        Cli::Run(args) => cli::run::<SamplingStage>(&args),
        Cli::Inspect(args) => cli::inspect::<SamplingStage>(&args),
    })
}
