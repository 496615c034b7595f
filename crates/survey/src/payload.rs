//! The survey artifact: the stations, the passage statistics beside the real caves' ranges,
//! and the void volume.

use std::collections::BTreeMap;

use serde::{Deserialize, Serialize};

use karst_artifact::check::{self, MAX_COORDINATE, ensure};
use karst_artifact::{Invalid, Payload, StageId};
use karst_skeleton::{ConduitType, Zone};

/// One survey station.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Station {
    /// The conduit, 1-based as in the other tables.
    pub conduit: u32,
    /// The station's number along its conduit, from 1.
    pub station: u32,
    /// Where it stands: on the centreline, world coordinates (metres).
    pub position: [f64; 3],
    /// Left + right: the horizontal chord through the measured point, metres (0: no open
    /// passage found).
    pub width: f64,
    /// Up + down: the vertical chord (a second horizontal chord in a shaft), metres.
    pub height: f64,
    /// Area of the open region of the cross-section, m².
    pub area: f64,
    /// Type of the segment the station lies on.
    pub kind: ConduitType,
    /// Zone of the nearer node of that segment.
    pub zone: Zone,
    /// Steeper than 45°: two horizontal chords, left out of the statistics.
    pub shaft: bool,
    /// Within one passage width of a junction: left out of the statistics.
    pub junction: bool,
}

/// One passage statistic beside the range of the surveyed caves.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct PassageStatistic {
    /// The value over the run's stations (None when too few stations define it).
    pub value: Option<f64>,
    pub min: f64,
    pub max: f64,
    /// Whether the value lies within [min, max].
    pub inside: bool,
}

/// Void volume of the cave, m³, per zone and per conduit type: each station's cross-section
/// area times the arc length it stands for.
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
pub struct VoidVolume {
    pub total: f64,
    pub zones: BTreeMap<String, f64>,
    pub conduit_types: BTreeMap<String, f64>,
}

/// The survey of a run.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Survey {
    /// Distance between stations along a conduit, metres.
    pub spacing: f64,
    pub stations: Vec<Station>,
    /// Stations in the statistics (not shafts, not at junctions, both chords > 0).
    pub counted: usize,
    /// The nine statistics of issue 39's table, under the names of passage-ranges.json.
    pub statistics: BTreeMap<String, PassageStatistic>,
    pub void_volume: VoidVolume,
}

impl Payload for Survey {
    const STAGE: StageId = StageId::Survey;
    const SCHEMA: u32 = 1;

    /// Stations numbered from 1 within each conduit, at finite positions, with chords and
    /// areas ≥ 0; finite volumes.
    fn validate(&self) -> Result<(), Invalid> {
        check::within(|| "spacing".into(), self.spacing, 1e-3, MAX_COORDINATE)?;
        for (i, s) in self.stations.iter().enumerate() {
            check::position(|| format!("stations[{i}].position"), &s.position)?;
            ensure(
                s.conduit >= 1 && s.station >= 1,
                || format!("stations[{i}]"),
                || "numbers start at 1".into(),
            )?;
            for (name, v) in [("width", s.width), ("height", s.height), ("area", s.area)] {
                check::within(|| format!("stations[{i}].{name}"), v, 0.0, f64::MAX)?;
            }
        }
        let volumes = self.void_volume.zones.values().chain(self.void_volume.conduit_types.values());
        for v in volumes.chain([&self.void_volume.total]) {
            check::within(|| "void_volume".into(), *v, 0.0, f64::MAX)?;
        }
        Ok(())
    }
}
