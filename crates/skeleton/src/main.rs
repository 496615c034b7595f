//! `karst-skeleton`: stage 3 of karstgen. `run SCENE --out DIR` writes DIR/skeleton.json and the karstnet export;
//! `inspect FILE [--json]` prints a summary or the whole artifact.

use std::process::ExitCode;

use clap::Parser;
use karst_skeleton::{SkeletonStage, stage};
use karst_stage::cli::{self, InspectArgs, RunArgs, default_sigpipe, finish};

/// The conduit network (karstgen stage 3).
#[derive(Parser)]
#[command(name = "karst-skeleton", version)]
enum Cli {
    /// Route the sinks to their springs on DIR/costgraph.bin into DIR/skeleton.json.
    Run(RunArgs),
    /// Summarize a skeleton artifact (or print it whole with --json).
    Inspect(InspectArgs),
    /// Draw a skeleton artifact: top and side views, conduits coloured by type, into a PNG.
    Render(stage::RenderArgs),
}

fn main() -> ExitCode {
    default_sigpipe();
    finish(match Cli::parse() {
        Cli::Run(args) => cli::run::<SkeletonStage>(&args),
        Cli::Inspect(args) => cli::inspect::<SkeletonStage>(&args),
        Cli::Render(args) => stage::render(&args),
    })
}
