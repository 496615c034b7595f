//! `karst-sdf`: stage 6 of karstgen. `run SCENE --out DIR` writes DIR/sdf.bin;
//! `inspect FILE [--json]` prints a summary or the whole artifact;
//! `slice FILE --z Z | --y Y | --x X --png PNG [--exr EXR]` writes a cross-section image;
//! `sections --png PNG` draws the cross-section library.

use std::process::ExitCode;

use clap::Parser;
use karst_sdf::{SdfStage, stage};
use karst_stage::cli::{self, InspectArgs, RunArgs, default_sigpipe, finish};

/// The signed-distance model of the carved terrain (karstgen stage 6).
#[derive(Parser)]
#[command(name = "karst-sdf", version)]
enum Cli {
    /// Build the SDF model of DIR/skeleton.json, DIR/hydro.json and DIR/streams.json into DIR/sdf.bin.
    Run(RunArgs),
    /// Summarize an sdf artifact (or print it whole with --json).
    Inspect(InspectArgs),
    /// Write a horizontal (--z) or vertical (--y, --x) slice of an sdf artifact as PNG and/or EXR.
    Slice(stage::SliceArgs),
    /// Draw the cross-section library (one section per conduit type) as a PNG.
    Sections(stage::SectionsArgs),
}

fn main() -> ExitCode {
    default_sigpipe();
    finish(match Cli::parse() {
        Cli::Run(args) => cli::run::<SdfStage>(&args),
        Cli::Inspect(args) => cli::inspect::<SdfStage>(&args),
        Cli::Slice(args) => stage::slice(&args),
        Cli::Sections(args) => stage::sections(&args),
    })
}
