//! `karst-streams`: the surface waterfall network. `run SCENE --out DIR` reads DIR/hydro.json
//! and writes DIR/streams.json; `render SCENE DIR` draws the map; `inspect FILE` summarises.
//! (Until the stage is registered in the pipeline, streams.json is plain JSON, no envelope.)

use std::process::ExitCode;

use clap::Parser;
use karst_artifact::cli::{RunArgs, default_sigpipe, finish};
use karst_streams::cli;

/// The surface streams, waterfalls and pools fed by the springs.
#[derive(Parser)]
#[command(name = "karst-streams", version)]
enum Cli {
    /// Trace the springs' water over the terrain: DIR/hydro.json in, DIR/streams.json out.
    Run(RunArgs),
    /// Draw the map of DIR/streams.json over the scene's terrain, coloured by water type.
    Render(cli::RenderArgs),
    /// Summarize a streams.json.
    Inspect(cli::InspectArgs),
}

fn main() -> ExitCode {
    default_sigpipe();
    finish(match Cli::parse() {
        Cli::Run(args) => cli::run(&args).map(|headline| println!("{headline}")),
        Cli::Render(args) => cli::render(&args),
        Cli::Inspect(args) => cli::inspect(&args),
    })
}
