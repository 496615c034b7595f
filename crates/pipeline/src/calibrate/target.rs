//! The network to match: a surveyed cave of the user's (`--target`: a karstnet `BASE_nodes.dat`
//! / `BASE_links.dat` pair (BASE or either file), a GOCAD PLine (`.pl`) or two CSV tables (nodes,
//! edges), read by the metrics crate's readers and characterised like any network), or a
//! published network (`--like NAME`: one of KNdata-public's, or `surveyed`, the median of each
//! statistic over its 25 surveyed caves).

use std::path::{Path, PathBuf};

use karst_metrics::published::{Published, PublishedNetwork};
use karst_metrics::{characterize, readers};
use karst_stage::StageError;

use super::evaluate::{MetricVector, metric_vector};
use super::objective::median;

/// `--like surveyed`: the median of the surveyed caves.
pub const SURVEYED: &str = "surveyed";

/// What the calibration aims at.
#[derive(Debug, Clone, PartialEq)]
pub enum Aim {
    /// A surveyed network: one file, or two CSV files (nodes, edges).
    Cave(Vec<PathBuf>),
    /// A published network by name (any case), or [`SURVEYED`].
    Like(String),
}

/// The target's name (its file, as given) and metrics.
pub struct Target {
    pub name: String,
    pub metrics: MetricVector,
}

/// The target `aim` names, characterised.
pub fn read(aim: &Aim) -> Result<Target, StageError> {
    match aim {
        Aim::Cave(files) => read_cave(files),
        Aim::Like(name) => like(&kndata()?, name),
    }
}

/// The published networks' names, surveyed caves then idealized patterns, for `--like list`.
pub fn like_names() -> Result<Vec<String>, StageError> {
    let published = kndata()?;
    let names = |networks: &mut dyn Iterator<Item = &PublishedNetwork>| {
        networks.map(|n| n.name.as_str()).collect::<Vec<_>>().join(", ")
    };
    Ok(vec![
        format!(
            "{SURVEYED}: the median of each statistic over the {} surveyed caves",
            published.surveyed().count()
        ),
        format!("surveyed caves: {}", names(&mut published.surveyed())),
        format!("idealized patterns: {}", names(&mut published.idealized())),
        "statistics computed with karstnet 1.2.5 from KNdata-public (ERC-Karst, 2024)".to_string(),
    ])
}

fn kndata() -> Result<Published, StageError> {
    Published::kndata().map_err(|e| StageError::failure(e.to_string()))
}

/// The published network `name` (any case) or, for [`SURVEYED`], the median of the surveyed
/// caves; an unknown name is bad input, answered with the names.
fn like(published: &Published, name: &str) -> Result<Target, StageError> {
    if name.eq_ignore_ascii_case(SURVEYED) {
        let caves: Vec<&PublishedNetwork> = published.surveyed().collect();
        let metrics = std::array::from_fn(|i| median(caves.iter().map(|c| c.statistics[i])));
        return Ok(Target { name: format!("median of {} surveyed caves", caves.len()), metrics });
    }
    match published.find(name) {
        Some(network) => Ok(Target { name: network.name.clone(), metrics: network.statistics }),
        None => Err(StageError::input(format!(
            "--like {name}: no published network of that name; give `{SURVEYED}`, one of {} \
             (`karstgen calibrate --like list` lists them)",
            published
                .surveyed()
                .chain(published.idealized())
                .map(|n| n.name.as_str())
                .collect::<Vec<_>>()
                .join(", ")
        ))),
    }
}

/// Reads and characterises the network in `files`; a file that cannot be read or whose network
/// cannot be characterised is bad input (exit 2), named.
fn read_cave(files: &[PathBuf]) -> Result<Target, StageError> {
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

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn like_takes_a_name_in_any_case_and_the_surveyed_median() {
        let published = Published::kndata().unwrap();
        let sakany = like(&published, "SAKANY").unwrap();
        assert_eq!(sakany.name, "Sakany");
        assert_eq!(sakany.metrics, published.find("Sakany").unwrap().statistics);
        let surveyed = like(&published, "Surveyed").unwrap();
        assert_eq!(surveyed.name, "median of 25 surveyed caves");
        for (i, m) in surveyed.metrics.iter().enumerate() {
            let below = published.surveyed().filter(|c| c.statistics[i] < *m).count();
            let above = published.surveyed().filter(|c| c.statistics[i] > *m).count();
            assert!(below <= 12 && above <= 12, "metric {i}: {below} below, {above} above {m}");
        }
    }

    #[test]
    fn an_unknown_name_is_refused_with_the_names() {
        let Err(e) = like(&Published::kndata().unwrap(), "Lascaux") else { panic!("Lascaux accepted") };
        assert_eq!(e.exit_code(), 2);
        let message = e.to_string();
        assert!(message.contains("--like Lascaux"), "{message}");
        assert!(message.contains("Sakany") && message.contains("PerfectTree45deg"), "{message}");
    }
}
