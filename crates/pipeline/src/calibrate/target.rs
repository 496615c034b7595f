//! The network to match: a surveyed cave of the user's (`--target`: a karstnet `BASE_nodes.dat`
//! / `BASE_links.dat` pair (BASE or either file), a GOCAD PLine (`.pl`) or two CSV tables (nodes,
//! edges), read by the metrics crate's readers and characterised like any network), or a
//! published network (`--like NAME`: one of KNdata-public's, or `surveyed`, the median of each
//! statistic over its 25 surveyed caves).

use std::path::PathBuf;

use karst_metrics::aim::{self, AimError};
use karst_metrics::published::{Published, PublishedNetwork};
use karst_stage::StageError;

use super::evaluate::MetricVector;

/// `--like surveyed`: the median of the surveyed caves.
pub const SURVEYED: &str = aim::SURVEYED;

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
    let target = match aim {
        Aim::Cave(files) => aim::cave(files).map_err(|e| bad_cave(files, e))?,
        Aim::Like(name) => aim::like(name).map_err(|e| bad_name(name, e))?,
    };
    Ok(Target { name: target.name, metrics: target.statistics })
}

/// What the scene's `[calibrate]` aims at (`like`, or `target` resolved against the scene's
/// folder), if it names one.
pub fn of_scene(scene: &karst_scene::Scene) -> Option<Aim> {
    match scene.calibrate().as_ref()?.aim()? {
        karst_scene::params::Aim::Like(name) => Some(Aim::Like(name.to_string())),
        karst_scene::params::Aim::Target { path, .. } => Some(Aim::Cave(vec![path.to_path_buf()])),
    }
}

fn bad_name(name: &str, e: AimError) -> StageError {
    match e {
        AimError::UnknownName { names, .. } => StageError::input(format!(
            "--like {name}: no published network of that name; give `{SURVEYED}`, one of {names} \
             (`karstgen calibrate --like list` lists them)"
        )),
        other => StageError::failure(other.to_string()),
    }
}

fn bad_cave(files: &[PathBuf], e: AimError) -> StageError {
    match e {
        AimError::OneCsv(_) if files.len() == 1 => StageError::input(format!(
            "{}: a CSV network is two files: --target NODES.csv EDGES.csv",
            files[0].display()
        )),
        AimError::OneCsv(_) => StageError::input("--target takes one network file, or two CSV files"),
        AimError::Read(e) => StageError::input(format!("calibration target: {e}")),
        other => StageError::input(other.to_string()),
    }
}

/// The published networks' names, surveyed caves then idealized patterns, for `--like list`.
pub fn like_names() -> Result<Vec<String>, StageError> {
    let published = Published::kndata().map_err(|e| StageError::failure(e.to_string()))?;
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

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn like_takes_a_name_in_any_case_and_the_surveyed_median() {
        let published = Published::kndata().unwrap();
        let sakany = read(&Aim::Like("SAKANY".into())).unwrap();
        assert_eq!(sakany.name, "Sakany");
        assert_eq!(sakany.metrics, published.find("Sakany").unwrap().statistics);
        let surveyed = read(&Aim::Like("Surveyed".into())).unwrap();
        assert_eq!(surveyed.name, "median of 25 surveyed caves");
        for (i, m) in surveyed.metrics.iter().enumerate() {
            let below = published.surveyed().filter(|c| c.statistics[i] < *m).count();
            let above = published.surveyed().filter(|c| c.statistics[i] > *m).count();
            assert!(below <= 12 && above <= 12, "metric {i}: {below} below, {above} above {m}");
        }
    }

    #[test]
    fn an_unknown_name_is_refused_with_the_names() {
        let Err(e) = read(&Aim::Like("Lascaux".into())) else { panic!("Lascaux accepted") };
        assert_eq!(e.exit_code(), 2);
        let message = e.to_string();
        assert!(message.contains("--like Lascaux"), "{message}");
        assert!(message.contains("Sakany") && message.contains("PerfectTree45deg"), "{message}");
    }
}
