//! `karst-streams`: stage 5 of karstgen. `run SCENE --out DIR` reads DIR/hydro.json and writes
//! DIR/streams.json; `render SCENE DIR` draws the map; `inspect FILE [--json]` prints a summary
//! or the whole artifact.

use std::process::ExitCode;

use clap::Parser;
use karst_stage::cli::{self, InspectArgs, RunArgs, default_sigpipe, finish};
use karst_streams::{StreamsStage, stage};

/// The surface streams, waterfalls and pools fed by the springs (karstgen stage 5).
#[derive(Parser)]
#[command(name = "karst-streams", version)]
enum Cli {
    /// Trace the springs' water over the terrain: DIR/hydro.json in, DIR/streams.json out.
    Run(RunArgs),
    /// Draw the map of DIR/streams.json over the scene's terrain, coloured by water type.
    Render(stage::RenderArgs),
    /// Summarize a streams artifact (or print it whole with --json).
    Inspect(InspectArgs),
}

fn main() -> ExitCode {
    default_sigpipe();
    finish(match Cli::parse() {
        Cli::Run(args) => cli::run::<StreamsStage>(&args),
        Cli::Render(args) => stage::render(&args),
        Cli::Inspect(args) => cli::inspect::<StreamsStage>(&args),
    })
}
