//! The stage contract: what every stage of karstgen is, and the one runner that runs them.
//!
//! A stage is a type implementing [`Stage`]: its row of the stage table (name, binary,
//! artifact file, encoding, inputs: [`karst_artifact::StageRow`]), its view of the scene (the
//! sections it reads, typed: [`karst_scene::view!`]), the upstream payloads it reads
//! ([`Inputs`]), the payload it writes, its own typed error and a `build` function from the
//! view and the inputs to the payload, plus a headline and an `inspect` summary. [`runner::run`] does everything around `build` the same way for every
//! stage: read and check the inputs, time the build, write the side files then the artifact
//! (atomically, keyed by the view's scene sections and the inputs), and report. [`cli`] turns the same
//! into a stage binary's `run` and `inspect` subcommands. A stage whose payload is too large to
//! hold in memory writes its artifact itself ([`Stage::write_streamed`], [`ArtifactOut`]).
//!
//! Library code returns its stage's typed error; only the runner and the command-line layers
//! turn errors into the [`StageError`] that carries the process exit code (2 for bad input,
//! 1 for a failure of karstgen or the machine), using the error's [`Blame`] to name the file
//! at fault.

pub mod cli;
mod contract;
mod error;
mod handoff;
pub mod human;
mod inputs;
pub mod progress;
pub mod run_dir;
pub mod runner;
mod streamed;

pub use contract::{Blame, Failure, Stage, sections};
pub use error::{Input, StageError};
pub use handoff::Handoff;
pub use inputs::Inputs;
pub use runner::{Job, Ran};
pub use streamed::{ArtifactOut, Written};
