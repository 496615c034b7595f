//! What every stage binary shares: the `run` and `inspect` subcommands, printing an artifact
//! as JSON, and exit codes.

use std::path::{Path, PathBuf};
use std::process::ExitCode;

use serde::Serialize;

use karst_artifact::{Header, Payload, read_artifact};
use karst_scene::Scene;
use karst_scene::budget::Budget;

use crate::contract::Stage;
use crate::error::StageError;
use crate::runner::{self, Job};

/// `karst-<stage> run SCENE [--out DIR]`.
#[derive(Debug, Clone, clap::Args)]
pub struct RunArgs {
    /// The scene file (TOML).
    pub scene: PathBuf,
    /// Folder holding the upstream artifacts; this stage's artifact is written there too.
    #[arg(long, default_value = "out")]
    pub out: PathBuf,
    /// Memory the stage may plan to use (e.g. 16G, 512M); above it, it refuses (docs/limits.md).
    #[arg(long, value_name = "SIZE")]
    pub max_memory: Option<Budget>,
}

/// `karst-<stage> inspect FILE [--json]`.
#[derive(Debug, Clone, clap::Args)]
pub struct InspectArgs {
    /// The artifact file.
    pub file: PathBuf,
    /// Print the whole artifact (header and payload) as JSON instead of a summary.
    #[arg(long)]
    pub json: bool,
}

/// `karst-<stage> run`: runs stage `S` on the scene and prints its headline.
pub fn run<S: Stage>(args: &RunArgs) -> Result<(), StageError> {
    let mut scene = Scene::load(&args.scene)?;
    if let Some(budget) = args.max_memory {
        scene.set_budget(budget);
    }
    let _lock = karst_artifact::lock_output(&args.out)?;
    runner::sweep_leftovers(&args.out);
    let ran = runner::run::<S>(&Job::new(&args.scene, &scene, &args.out))?;
    println!("{} in {:.2} s", ran.headline, ran.seconds);
    for note in &ran.notes {
        eprintln!("note: {note}");
    }
    Ok(())
}

/// `karst-<stage> inspect`: the summary, or the whole artifact as JSON with `--json`.
pub fn inspect<S: Stage>(args: &InspectArgs) -> Result<(), StageError> {
    if args.json {
        return print_json::<S::Output>(&args.file);
    }
    for line in runner::inspect::<S>(&args.file)? {
        println!("{line}");
    }
    Ok(())
}

/// Prints an artifact as JSON: `{"header": …, "payload": …}`.
pub fn print_json<P: Payload>(path: &Path) -> Result<(), StageError> {
    let (header, payload) = read_artifact::<P>(path)?;
    #[derive(Serialize)]
    struct Whole<'a, P> {
        header: &'a Header,
        payload: &'a P,
    }
    let text = serde_json::to_string_pretty(&Whole { header: &header, payload: &payload })
        .map_err(|e| StageError::failure(format!("cannot print {}: {e}", path.display())))?;
    println!("{text}");
    Ok(())
}

/// Lets the process end quietly when its output is closed early (`karst-mesher inspect ... |
/// head`), as command-line tools do, instead of panicking in `println!` on a broken pipe:
/// Rust ignores SIGPIPE by default, so a write to a closed pipe is an error that `println!`
/// turns into a panic. Call it first in `main`.
#[allow(unsafe_code)]
pub fn default_sigpipe() {
    #[cfg(unix)]
    // SAFETY: restoring a signal's default disposition at start-up, before any thread exists.
    unsafe {
        libc::signal(libc::SIGPIPE, libc::SIG_DFL);
    }
}

/// Turns a result into the process exit code, printing the error on stderr.
pub fn finish(result: Result<(), StageError>) -> ExitCode {
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("error: {e}");
            ExitCode::from(e.exit_code())
        }
    }
}
