//! karstnet's ten `characterize_graph()` statistics of published networks, to calibrate a scene
//! towards one of them without a survey of one's own (`karstgen calibrate --like NAME`).
//!
//! The networks are those of KNdata-public (ERC-Karst, 2024): 25 surveyed caves and 8 idealized
//! pattern networks (Palmer's anastomotic, curvilinear and rectilinear branchwork, rectilinear
//! maze; perfect trees, grids and mazes). The statistics were computed for this project with
//! karstnet 1.2.5 and are embedded at build time (`data/kndata-metrics.json`, source and
//! licence in `data/SOURCE.md`); the survey data themselves are not.

use std::collections::BTreeMap;

use serde::Deserialize;

use crate::ranges::CHARACTERIZE_KEYS;

const KNDATA_JSON: &str = include_str!("../data/kndata-metrics.json");

/// The ten statistics of a network, in karstnet's order (NaN where karstnet left one undefined).
pub type Statistics = [f64; CHARACTERIZE_KEYS.len()];

/// A statistics file that cannot be used, naming the network and the key at fault.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum PublishedError {
    #[error("published statistics: not the expected JSON: {0}")]
    Json(String),
    #[error("published statistics: network \"{network}\" has no \"{key}\"")]
    MissingStatistic { network: String, key: &'static str },
    #[error("published statistics: \"{0}\" is listed as idealized but has no statistics")]
    UnknownIdealized(String),
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct KndataFile {
    #[serde(rename = "licence")]
    _licence: String,
    #[serde(rename = "source")]
    _source: String,
    idealized: Vec<String>,
    networks: BTreeMap<String, BTreeMap<String, Option<f64>>>,
}

/// One published network: its name and statistics, and whether it is an idealized pattern.
#[derive(Debug, Clone, PartialEq)]
pub struct PublishedNetwork {
    pub name: String,
    pub idealized: bool,
    pub statistics: Statistics,
}

/// The published networks, in name order.
#[derive(Debug, Clone, PartialEq)]
pub struct Published {
    networks: Vec<PublishedNetwork>,
}

impl Published {
    /// The networks of KNdata-public embedded in karstgen.
    pub fn kndata() -> Result<Published, PublishedError> {
        Published::parse(KNDATA_JSON)
    }

    /// Reads a statistics file in the layout of `data/kndata-metrics.json`: every network must
    /// carry all ten keys (a `null` value is a statistic karstnet left undefined).
    pub fn parse(text: &str) -> Result<Published, PublishedError> {
        let file: KndataFile = serde_json::from_str(text).map_err(|e| PublishedError::Json(e.to_string()))?;
        if let Some(unknown) = file.idealized.iter().find(|name| !file.networks.contains_key(*name)) {
            return Err(PublishedError::UnknownIdealized(unknown.clone()));
        }
        let networks = file
            .networks
            .iter()
            .map(|(name, values)| {
                let statistics = statistics(name, values)?;
                Ok(PublishedNetwork {
                    name: name.clone(),
                    idealized: file.idealized.contains(name),
                    statistics,
                })
            })
            .collect::<Result<Vec<_>, PublishedError>>()?;
        Ok(Published { networks })
    }

    /// The network called `name`, whatever its case.
    pub fn find(&self, name: &str) -> Option<&PublishedNetwork> {
        self.networks.iter().find(|n| n.name.eq_ignore_ascii_case(name))
    }

    /// The surveyed caves (not the idealized patterns).
    pub fn surveyed(&self) -> impl Iterator<Item = &PublishedNetwork> {
        self.networks.iter().filter(|n| !n.idealized)
    }

    /// The idealized pattern networks.
    pub fn idealized(&self) -> impl Iterator<Item = &PublishedNetwork> {
        self.networks.iter().filter(|n| n.idealized)
    }
}

fn statistics(network: &str, values: &BTreeMap<String, Option<f64>>) -> Result<Statistics, PublishedError> {
    let mut statistics = [f64::NAN; CHARACTERIZE_KEYS.len()];
    for (slot, key) in statistics.iter_mut().zip(CHARACTERIZE_KEYS) {
        let value = values
            .get(key)
            .ok_or_else(|| PublishedError::MissingStatistic { network: network.to_string(), key })?;
        *slot = value.unwrap_or(f64::NAN);
    }
    Ok(statistics)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn kndata_holds_25_surveyed_caves_and_8_patterns() {
        let published = Published::kndata().unwrap();
        assert_eq!(published.surveyed().count(), 25);
        assert_eq!(published.idealized().count(), 8);
        let sakany = published.find("sakany").unwrap();
        assert_eq!(sakany.name, "Sakany");
        assert!(!sakany.idealized);
        assert!(published.find("perfecttree45DEG").unwrap().idealized);
        assert!(published.find("Lascaux").is_none());
    }

    #[test]
    fn a_network_without_a_statistic_is_named() {
        let text = r#"{"licence": "l", "source": "s", "idealized": [],
            "networks": {"Cave": {"mean length": 10.0}}}"#;
        assert_eq!(
            Published::parse(text),
            Err(PublishedError::MissingStatistic { network: "Cave".into(), key: "cv length" })
        );
    }

    #[test]
    fn a_pattern_without_statistics_and_bad_json_are_refused() {
        let text = r#"{"licence": "l", "source": "s", "idealized": ["Grid"], "networks": {}}"#;
        assert_eq!(Published::parse(text), Err(PublishedError::UnknownIdealized("Grid".into())));
        let text = r#"{"licence": "l", "source": "s", "idealized": [], "networks": {"Cave": {"cpd": "x"}}}"#;
        assert!(matches!(Published::parse(text), Err(PublishedError::Json(_))));
    }
}
