//! What every stage binary shares: the `run` and `inspect` arguments, reading upstream
//! artifacts, building the provenance of the artifact it writes, and exit codes.

use std::path::{Path, PathBuf};
use std::process::ExitCode;

use serde::Serialize;

use crate::envelope::{Header, InputRef, Payload, Provenance, read_artifact};
use crate::error::StageError;
use crate::pipeline::{Stage, producer};

/// `karst-<stage> run SCENE [--out DIR]`.
#[derive(Debug, Clone, clap::Args)]
pub struct RunArgs {
    /// The scene file (TOML).
    pub scene: PathBuf,
    /// Folder holding the upstream artifacts; this stage's artifact is written there too.
    #[arg(long, default_value = "out")]
    pub out: PathBuf,
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

/// One run of one stage: where its inputs are and how to label what it writes.
#[derive(Debug, Clone)]
pub struct StageRun {
    pub stage: Stage,
    pub out_dir: PathBuf,
    inputs: Vec<InputRef>,
}

impl StageRun {
    /// Starts a run of `stage` writing into `out_dir`.
    pub fn new(stage: Stage, out_dir: &Path) -> Self {
        StageRun { stage, out_dir: out_dir.to_path_buf(), inputs: Vec::new() }
    }

    /// Path of `stage`'s artifact in the output folder.
    pub fn path_of(&self, stage: Stage) -> PathBuf {
        self.out_dir.join(stage.file_name())
    }

    /// Reads an upstream artifact and records its payload hash for this run's key.
    pub fn read_input<P: Payload>(&mut self, stage: Stage) -> Result<P, StageError> {
        debug_assert!(self.stage.inputs().contains(&stage));
        let (header, payload) = read_artifact::<P>(&self.path_of(stage))?;
        self.inputs
            .push(InputRef { name: stage.kind().name().into(), payload_blake3: header.payload_blake3 });
        Ok(payload)
    }

    /// The provenance of this run's artifact, given the hash of the scene sections it read.
    pub fn provenance(&self, params: &str) -> Provenance {
        Provenance { producer: producer(self.stage), inputs: self.inputs.clone(), params: params.to_string() }
    }

    /// Path of this run's own artifact.
    pub fn output_path(&self) -> PathBuf {
        self.path_of(self.stage)
    }
}

/// Prints an artifact as JSON: `{"header": …, "payload": …}`.
pub fn print_json<P: Payload + Serialize>(path: &Path) -> Result<(), StageError> {
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
pub fn default_sigpipe() {
    #[cfg(unix)]
    // SAFETY: restoring a signal's default disposition at start-up, before any thread exists.
    unsafe {
        libc::signal(libc::SIGPIPE, libc::SIG_DFL);
    }
}

/// Turns a stage result into the process exit code, printing the error on stderr.
pub fn finish(result: Result<(), StageError>) -> ExitCode {
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("error: {e}");
            ExitCode::from(e.exit_code())
        }
    }
}
