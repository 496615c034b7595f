//! karstgen's developer tasks, as a library so that tests drive exactly what `cargo xtask` does.
//!
//! - [`bless`]: review the tiny scene's artifacts against the goldens, replace them with a reason;
//! - [`bench`]: time every stage on the benchmark scenes and each stage's budget cases;
//! - [`peer`]: time the network half beside KarstNSim;
//! - [`regional`]: every stage on the regional scene, at two sizes;
//! - [`metrics_table`]: table every scene's metrics against the real caves;
//! - [`modules`]: the module-graph check, no import circle inside any crate;
//! - [`ensemble_table`]: the presets' metrics over many seeds against the real caves;
//! - [`realism`]: the network defaults on a generated population of scenes (issue 38);
//! - [`python`]: build and install the Python package's wheel and run its pytest suite;
//! - [`tools`]: install the outside programs the tests check outputs with;
//! - [`temp_folder`]: the tasks' scratch folders, removed however the task ends.
//!
//! Running the pipeline, diffs and ensembles are `karstgen`'s (crates/pipeline).

pub mod bench;
pub mod bless;
pub mod ensemble_table;
pub mod metrics_table;
pub mod modules;
pub mod peer;
pub mod python;
pub mod realism;
pub mod regional;
pub mod temp_folder;
pub mod tools;
