//! `karst-survey`: stage 8 of karstgen.
//!
//! - `run SCENE --out DIR` writes DIR/survey.json and DIR/passages.csv from DIR/skeleton.json
//!   and DIR/sdf.bin;
//! - `inspect FILE [--json]` prints a summary or the whole artifact.

use std::process::ExitCode;

use clap::{Parser, Subcommand};
use karst_stage::cli::{self, InspectArgs, RunArgs, default_sigpipe, finish};
use karst_survey::SurveyStage;

/// The passages measured as a cave survey would (karstgen stage 8).
#[derive(Parser)]
#[command(name = "karst-survey", version)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand)]
enum Command {
    /// Survey DIR/skeleton.json's conduits on DIR/sdf.bin into DIR/survey.json and passages.csv.
    Run(RunArgs),
    /// Summarize a survey artifact (or print it whole with --json).
    Inspect(InspectArgs),
}

fn main() -> ExitCode {
    default_sigpipe();
    finish(match Cli::parse().command {
        Command::Run(args) => cli::run::<SurveyStage>(&args),
        Command::Inspect(args) => cli::inspect::<SurveyStage>(&args),
    })
}
