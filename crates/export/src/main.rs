//! `karst-export`: stage 9 of karstgen, and exports of any run on demand.
//!
//! - `run SCENE --out DIR` writes the scene's `[export]` formats into DIR/export/ and their
//!   manifest into DIR/export.json;
//! - `inspect FILE [--json]` prints a summary of export.json or the whole artifact;
//! - `karst-export DIR [--format vtk,gocad,...] [--scene SCENE] [--json] [--budget MB]` writes
//!   any formats of the run in DIR (docs/exports.md), reading only the artifacts they need, after
//!   printing their estimated bytes (refused beyond the budget).

use std::process::ExitCode;

use clap::{Parser, Subcommand};
use karst_export::ExportStage;
use karst_export::stage::{ExportArgs, export_run};
use karst_stage::cli::{self, InspectArgs, RunArgs, default_sigpipe, finish};

/// Exports a karstgen run for ParaView, GOCAD, Survex, EPA SWMM, glTF viewers and spreadsheets.
#[derive(Parser)]
#[command(name = "karst-export", version, args_conflicts_with_subcommands = true)]
struct Cli {
    #[command(subcommand)]
    command: Option<Command>,
    #[command(flatten)]
    files: Option<ExportArgs>,
}

#[derive(Subcommand)]
enum Command {
    /// Write the scene's export formats of DIR into DIR/export/ and DIR/export.json.
    Run(RunArgs),
    /// Summarize an export artifact (or print it whole with --json).
    Inspect(InspectArgs),
}

fn main() -> ExitCode {
    default_sigpipe();
    let cli = Cli::parse();
    finish(match (cli.command, cli.files) {
        (Some(Command::Run(args)), _) => cli::run::<ExportStage>(&args),
        (Some(Command::Inspect(args)), _) => cli::inspect::<ExportStage>(&args),
        (None, Some(args)) => export_run(&args),
        (None, None) => {
            Err(karst_stage::StageError::input("give a subcommand (run, inspect) or a run folder"))
        }
    })
}
