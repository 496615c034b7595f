//! The metrics artifact, `metrics.json`: karstnet's statistics beside their real-cave ranges,
//! and what only a karstgen network knows (lengths per zone, conduit type and water type, and
//! the surface streams' lengths per water type and falls).

use std::collections::BTreeMap;

use serde::{Deserialize, Serialize};

use karst_artifact::check;
use karst_artifact::{Invalid, Payload, StageId};

use karst_survey::{PassageStatistic, VoidVolume};

use crate::Metrics;
use crate::ranges::Compared;

/// The metrics artifact.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct MetricsReport {
    /// `characterize_graph()`'s metrics, each with its real-cave range.
    pub karstnet: BTreeMap<String, Compared>,
    /// Every statistic, under karstnet's key names.
    pub network: Metrics,
    /// Conduit length in the vadose and the phreatic zone.
    pub zones: ZoneLengths,
    /// Conduit length per conduit type (every type, zero when absent).
    pub conduit_types: BTreeMap<String, f64>,
    /// Conduit length per water type of the hydro stage (every type, zero when absent); empty
    /// when the report is made from a skeleton alone (ensembles).
    #[serde(default)]
    pub water_types: BTreeMap<String, f64>,
    /// The surface streams of the streams stage; empty when the report is made from a skeleton
    /// alone (ensembles).
    #[serde(default)]
    pub surface: SurfaceWater,
    /// The passages as surveyed (survey.json): issue 39's nine statistics of the widths and
    /// heights beside the range of 17 surveyed caves; empty when the report is made from a
    /// skeleton alone (ensembles).
    #[serde(default, skip_serializing_if = "BTreeMap::is_empty")]
    pub passages: BTreeMap<String, PassageStatistic>,
    /// The cave's void volume per zone and conduit type (survey.json), m³.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub void_volume: Option<VoidVolume>,
    /// For each karstnet metric outside its real-cave range, a hint in plain words with the
    /// parameter that moves it and its value in the run (`hints.rs`); empty for reports made
    /// from a skeleton alone.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub hints: Vec<String>,
    /// The run against the scene's calibration target (`[calibrate] like` or `target`), when it
    /// names one; the hints are then relative to it.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub target: Option<crate::hints::TargetVerdict>,
}

/// The surface streams fed by the springs (streams.json).
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
pub struct SurfaceWater {
    /// Length per water type (every type, zero when absent; a fall along its parabola), metres.
    pub water_types: BTreeMap<String, f64>,
    /// Number of free falls.
    pub falls: usize,
}

/// Conduit length above (vadose) and below (phreatic) the water table, metres.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct ZoneLengths {
    pub vadose: f64,
    pub phreatic: f64,
}

impl Payload for MetricsReport {
    const STAGE: StageId = StageId::Metrics;
    const SCHEMA: u32 = 5;

    /// Lengths finite and ≥ 0 (the statistics themselves may be undefined, written `null`).
    fn validate(&self) -> Result<(), Invalid> {
        let length = |field: String, value: f64| check::within(|| field, value, 0.0, f64::MAX);
        length("zones.vadose".into(), self.zones.vadose)?;
        length("zones.phreatic".into(), self.zones.phreatic)?;
        for (kind, value) in &self.conduit_types {
            length(format!("conduit_types.{kind}"), *value)?;
        }
        for (kind, value) in &self.water_types {
            length(format!("water_types.{kind}"), *value)?;
        }
        for (kind, value) in &self.surface.water_types {
            length(format!("surface.water_types.{kind}"), *value)?;
        }
        Ok(())
    }
}
