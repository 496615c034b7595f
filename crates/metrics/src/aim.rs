//! The network a run aims at: a published network by name (`[calibrate] like`, `--like`), the
//! median of the surveyed caves (`surveyed`), or a surveyed cave's file (`[calibrate] target`,
//! `--target`), each reduced to karstnet's ten `characterize_graph()` statistics; and how far a
//! network is from it.
//!
//! The distance normalises each metric's difference by the width of its range over real caves
//! (Collon et al. 2017), so that a metric counts by how far it moves across real caves rather
//! than by its unit; the calibration minimises it and the verdict of a calibrated run reports
//! it.

use std::path::{Path, PathBuf};

use crate::published::{Published, PublishedError, PublishedNetwork, Statistics};
use crate::ranges::{CHARACTERIZE_KEYS, real_cave_ranges};
use crate::readers::{self, ReadError};
use crate::{MetricsError, characterize};

/// `like = "surveyed"`: the median of each statistic over the surveyed caves.
pub const SURVEYED: &str = "surveyed";

/// The normalised difference of a metric the network leaves undefined: a whole real-cave range.
pub const UNDEFINED: f64 = 1.0;

/// A metric is on target when it lies within this fraction of its real-cave range of the
/// target's value: a tenth of the spread of real caves is below what separates two caves of
/// the same massif.
pub const ON_TARGET: f64 = 0.1;

/// The network aimed at: its name and its statistics in karstnet's order (NaN: undefined).
#[derive(Debug, Clone, PartialEq)]
pub struct Target {
    pub name: String,
    pub statistics: Statistics,
}

/// Why the aim cannot be resolved.
#[derive(Debug, thiserror::Error)]
pub enum AimError {
    #[error("no published network \"{name}\"; give `{SURVEYED}` or one of {names}")]
    UnknownName { name: String, names: String },
    #[error("{0}")]
    Read(#[from] ReadError),
    #[error("{file}: {source}")]
    Network { file: String, source: MetricsError },
    #[error("{0}: a CSV network is two files (nodes, edges)")]
    OneCsv(String),
    #[error(
        "{file}: unknown network format .{extension}: give karstnet's BASE_nodes.dat (or BASE) or a GOCAD PLine .pl"
    )]
    Format { file: String, extension: String },
    #[error("{0}")]
    Published(#[from] PublishedError),
}

/// The published network `name` (any case) or, for [`SURVEYED`], the median of the surveyed
/// caves.
pub fn like(name: &str) -> Result<Target, AimError> {
    let published = Published::kndata()?;
    if name.eq_ignore_ascii_case(SURVEYED) {
        let caves: Vec<&PublishedNetwork> = published.surveyed().collect();
        let statistics = std::array::from_fn(|i| median(caves.iter().map(|c| c.statistics[i])));
        return Ok(Target { name: format!("median of {} surveyed caves", caves.len()), statistics });
    }
    match published.find(name) {
        Some(network) => Ok(Target { name: network.name.clone(), statistics: network.statistics }),
        None => Err(AimError::UnknownName {
            name: name.to_string(),
            names: published
                .surveyed()
                .chain(published.idealized())
                .map(|n| n.name.as_str())
                .collect::<Vec<_>>()
                .join(", "),
        }),
    }
}

/// The surveyed cave in `files`: one karstnet or PLine file, or two CSV files (nodes, edges),
/// read and characterised.
pub fn cave(files: &[PathBuf]) -> Result<Target, AimError> {
    let (network, name) = match files {
        [nodes, edges] => (readers::read_csv(nodes, edges)?, nodes.display().to_string()),
        [file] => (read_one(file)?, file.display().to_string()),
        _ => return Err(AimError::OneCsv(files.iter().map(|f| f.display().to_string()).collect())),
    };
    let metrics =
        characterize(&network).map_err(|source| AimError::Network { file: name.clone(), source })?;
    Ok(Target { name, statistics: statistics_of(&metrics) })
}

fn read_one(file: &Path) -> Result<crate::Network, AimError> {
    let extension = file.extension().map(|e| e.to_string_lossy().to_ascii_lowercase());
    match extension.as_deref() {
        Some("pl") => Ok(readers::read_pline(file)?),
        Some("dat") | None => Ok(readers::read_karstnet(file)?),
        Some("csv") => Err(AimError::OneCsv(file.display().to_string())),
        Some(other) => {
            Err(AimError::Format { file: file.display().to_string(), extension: other.to_string() })
        }
    }
}

/// The `characterize_graph()` statistics of `metrics`, in karstnet's order.
pub fn statistics_of(metrics: &crate::Metrics) -> Statistics {
    let pairs = metrics.to_pairs();
    CHARACTERIZE_KEYS.map(|key| pairs.iter().find(|(k, _)| *k == key).map_or(f64::NAN, |(_, v)| *v))
}

/// The width of each metric's real-cave range, in karstnet's order.
pub fn widths() -> Statistics {
    let ranges = real_cave_ranges();
    CHARACTERIZE_KEYS.map(|key| ranges[key].max - ranges[key].min)
}

/// How far a metric is from the target's, in real-cave ranges (signed: positive above);
/// [`UNDEFINED`] when the network leaves it undefined, None when the target does.
pub fn normalised(value: f64, target: f64, width: f64) -> Option<f64> {
    if !target.is_finite() {
        return None;
    }
    let d = (value - target) / width;
    Some(if d.is_finite() { d } else { UNDEFINED })
}

/// The distance of a network with `statistics` to the target: the root mean square of the
/// normalised differences of the metrics the target defines.
pub fn distance(statistics: &Statistics, target: &Statistics, widths: &Statistics) -> f64 {
    let terms: Vec<f64> =
        (0..statistics.len()).filter_map(|i| normalised(statistics[i], target[i], widths[i])).collect();
    (terms.iter().map(|d| d * d).sum::<f64>() / terms.len().max(1) as f64).sqrt()
}

/// The median of the finite values (the mean of the middle two for an even count); NaN when
/// none is finite.
pub fn median(values: impl IntoIterator<Item = f64>) -> f64 {
    let mut v: Vec<f64> = values.into_iter().filter(|x| x.is_finite()).collect();
    v.sort_by(f64::total_cmp);
    match v.len() {
        0 => f64::NAN,
        n if n % 2 == 1 => v[n / 2],
        n => (v[n / 2 - 1] + v[n / 2]) / 2.0,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_distance_is_zero_on_the_target_and_counts_ranges() {
        let target: Statistics = [20.0, 1.0, 0.4, 1.3, 0.99, 12.0, 0.3, 2.4, 0.5, -0.2];
        let w = widths();
        assert_eq!(distance(&target, &target, &w), 0.0);
        let mut one_range_off = target;
        one_range_off[6] += w[6];
        assert!((distance(&one_range_off, &target, &w) - (0.1f64).sqrt()).abs() < 1e-12);
        let mut undefined = target;
        undefined[3] = f64::NAN;
        assert!((distance(&undefined, &target, &w) - (0.1f64).sqrt()).abs() < 1e-12);
        let mut left_out = target;
        left_out[3] = f64::NAN;
        let mut m = target;
        m[3] = 5.0;
        assert_eq!(distance(&m, &left_out, &w), 0.0);
    }

    #[test]
    fn like_takes_any_case_and_refuses_an_unknown_name_with_the_names() {
        assert_eq!(like("SAKANY").unwrap().name, "Sakany");
        assert_eq!(like("Surveyed").unwrap().name, "median of 25 surveyed caves");
        let message = like("Lascaux").unwrap_err().to_string();
        assert!(message.contains("\"Lascaux\"") && message.contains("Sakany"), "{message}");
    }
}
