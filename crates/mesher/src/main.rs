//! `karst-mesher`: stage 7 of karstgen. `run SCENE --out DIR` writes DIR/mesh.bin, DIR/mesh.obj
//! and DIR/export/; `inspect FILE [--json]` prints a summary or the whole artifact;
//! `render FILE --png OUT` draws a preview.

use std::process::ExitCode;

use clap::Parser;
use karst_mesher::{MesherStage, stage};
use karst_stage::cli::{self, InspectArgs, RunArgs, default_sigpipe, finish};

/// Sparse polygonization of the carved terrain and its caves (karstgen stage 7).
#[derive(Parser)]
#[command(name = "karst-mesher", version)]
enum Cli {
    /// Polygonize DIR/sdf.bin into DIR/mesh.bin, DIR/mesh.obj and DIR/export/.
    Run(RunArgs),
    /// Summarize a mesh artifact (or print it whole with --json).
    Inspect(InspectArgs),
    /// Render one surface of a mesh artifact to PNG.
    Render(stage::RenderArgs),
}

fn main() -> ExitCode {
    default_sigpipe();
    finish(match Cli::parse() {
        Cli::Run(args) => cli::run::<MesherStage>(&args),
        Cli::Inspect(args) => cli::inspect::<MesherStage>(&args),
        Cli::Render(args) => stage::render(&args),
    })
}
