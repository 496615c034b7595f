//! `karst-mesher`: stage 6 of karstgen. `run SCENE --out DIR` writes DIR/mesh.bin and DIR/mesh.obj;
//! `inspect FILE [--json]` prints a summary or the whole artifact.

use std::process::ExitCode;

use clap::Parser;
use karst_artifact::cli::{InspectArgs, RunArgs, finish};
use karst_mesher::stage;

/// Poisson-disk sampling of the bedrock (karstgen stage 6).
#[derive(Parser)]
#[command(name = "karst-mesher", version)]
enum Cli {
    /// Polygonize DIR/sdf.bin into DIR/mesh.bin and DIR/mesh.obj.
    Run(RunArgs),
    /// Summarize a mesh artifact (or print it whole with --json).
    Inspect(InspectArgs),
}

fn main() -> ExitCode {
    finish(match Cli::parse() {
        Cli::Run(args) => stage::run(&args).map(|headline| println!("{headline}")),
        Cli::Inspect(args) => stage::inspect(&args),
    })
}
