//! `karst-hydro`: stage 4 of karstgen. `run SCENE --out DIR` writes DIR/hydro.json and the CSV
//! tables; `render DIR` draws the water types; `inspect FILE [--json]` prints a summary or the
//! whole artifact.

use std::process::ExitCode;

use clap::Parser;
use karst_hydro::{HydroStage, stage};
use karst_stage::cli::{self, InspectArgs, RunArgs, default_sigpipe, finish};

/// Underground hydrology: flows, water types and water geometry (karstgen stage 4).
#[derive(Parser)]
#[command(name = "karst-hydro", version)]
enum Cli {
    /// Compute the water of DIR/skeleton.json into DIR/hydro.json and DIR/hydro_*.csv.
    Run(RunArgs),
    /// Draw DIR's network coloured by water type (top and side views) into a PNG.
    Render(stage::RenderArgs),
    /// Summarize a hydro artifact (or print it whole with --json).
    Inspect(InspectArgs),
}

fn main() -> ExitCode {
    default_sigpipe();
    finish(match Cli::parse() {
        Cli::Run(args) => cli::run::<HydroStage>(&args),
        Cli::Render(args) => stage::render(&args),
        Cli::Inspect(args) => cli::inspect::<HydroStage>(&args),
    })
}
