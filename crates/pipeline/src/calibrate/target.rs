//! The surveyed cave to match: a karstnet `BASE_nodes.dat` / `BASE_links.dat` pair (BASE or
//! either file), a GOCAD PLine (`.pl`) or two CSV tables (nodes, edges), read by the metrics
//! crate's readers and characterised like any network.

use std::path::{Path, PathBuf};

use karst_metrics::{characterize, readers};
use karst_stage::StageError;

use super::evaluate::{MetricVector, metric_vector};

/// The target's name (its file, as given) and metrics.
pub struct Target {
    pub name: String,
    pub metrics: MetricVector,
}

/// Reads and characterises the network in `files`; a file that cannot be read or whose network
/// cannot be characterised is bad input (exit 2), named.
pub fn read(files: &[PathBuf]) -> Result<Target, StageError> {
    let bad = |e: readers::ReadError| StageError::input(format!("calibration target: {e}"));
    let (network, name) = match files {
        [nodes, edges] => (readers::read_csv(nodes, edges).map_err(bad)?, nodes.display().to_string()),
        [file] => match extension(file).as_deref() {
            Some("pl") => (readers::read_pline(file).map_err(bad)?, file.display().to_string()),
            Some("dat") | None => (readers::read_karstnet(file).map_err(bad)?, file.display().to_string()),
            Some("csv") => {
                return Err(StageError::input(format!(
                    "{}: a CSV network is two files: --target NODES.csv EDGES.csv",
                    file.display()
                )));
            }
            Some(other) => {
                return Err(StageError::input(format!(
                    "{}: unknown network format .{other}: give karstnet's BASE_nodes.dat (or BASE), \
                     a GOCAD PLine .pl, or two CSV files NODES EDGES",
                    file.display()
                )));
            }
        },
        _ => return Err(StageError::input("--target takes one network file, or two CSV files")),
    };
    let metrics = characterize(&network).map_err(|e| StageError::input(format!("{name}: {e}")))?;
    Ok(Target { name, metrics: metric_vector(&metrics) })
}

fn extension(path: &Path) -> Option<String> {
    path.extension().map(|e| e.to_string_lossy().to_ascii_lowercase())
}
