//! karstgen's task runner, as a library so that tests drive exactly what `cargo xtask` does.
//!
//! - [`pipeline`]: run the stages in order like make, skipping up-to-date artifacts;
//! - [`diff`]: compare two artifacts of the same kind semantically;
//! - [`bench`]: time every stage on the benchmark scenes;
//! - [`geodata_bench`]: the GeoTIFF terrain budget;
//! - [`ensemble`]: run many seeds of a scene and gather their statistics;
//! - [`metrics_table`]: table every scene's metrics against the real caves;
//! - [`tools`]: install the outside programs the tests check outputs with.

pub mod bench;
pub mod diff;
pub mod ensemble;
pub mod executor;
pub mod geodata_bench;
pub mod metrics_table;
pub mod pipeline;
pub mod tools;
