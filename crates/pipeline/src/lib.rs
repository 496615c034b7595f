//! karstgen's pipeline: the stages of the table run in order like make, in this process, plus what
//! works across stages: inspecting or diffing any artifact, and ensembles of realizations.
//!
//! - [`registry`]: the one place that maps a stage of the table to the type implementing it;
//! - [`make`]: run the stages in order, skipping those whose artifact is up to date;
//! - [`budget`]: the output budget, held against the mesher's work estimate before it runs;
//! - [`verdict`]: the closing lines of a run: the metrics inside the real-cave ranges, hints;
//! - [`scene`]: where a run's scene comes from (a file, or the embedded default scene);
//! - [`diff`]: compare two artifacts of the same kind semantically;
//! - [`ensemble`]: many realizations of one scene, differing only by seed;
//! - [`calibrate`]: the network parameters that bring a scene closest to a surveyed cave.
//!
//! The `karstgen` command and `cargo xtask` are thin layers over this crate.

pub mod budget;
pub mod calibrate;
pub mod diff;
pub mod ensemble;
pub mod make;
pub mod options;
pub mod registry;
pub mod scene;
pub mod verdict;
