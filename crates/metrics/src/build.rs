//! The report of a network: karstnet's statistics, lengths per zone, conduit type and water
//! type.
//!
//! `metrics.json` holds, under karstnet's key names, every `characterize_graph()` metric beside
//! its real-cave range (`karstnet`), every statistic of [`Metrics`] (`network`), and what only a
//! karstgen skeleton knows: the conduit length above and below the water table (`zones`) and per
//! conduit type (`conduit_types`, Paris et al. 2021 §5.3). A segment whose two nodes lie in
//! different zones crosses the water table somewhere between them: half of its length counts in
//! each zone.
//!
//! The passages' statistics and the void volume are the survey stage's (survey.json), copied.
//!
//! The length per water type (`water_types`: stream, rapid, plunge, sump, pool, dry... of the
//! hydro stage, Emilien et al. 2015 Table 1) sums each segment under the type hydro gave it;
//! `surface` does the same for the streams on the terrain (streams.json) and counts their free
//! falls.

use std::collections::BTreeMap;

use karst_hydro::{Hydro, WaterType};
use karst_skeleton::{ConduitType, Skeleton, Zone};
use karst_streams::Streams;
use karst_survey::Survey;

use crate::error::ReportError;
use crate::payload::{MetricsReport, SurfaceWater, ZoneLengths};
use crate::ranges;
use crate::{Network, characterize};

/// The report of `skeleton`, of its water in `hydro`, of the surface water in `streams` and of
/// the passages in `survey`.
pub fn build(
    skeleton: &Skeleton,
    hydro: &Hydro,
    streams: &Streams,
    survey: &Survey,
) -> Result<MetricsReport, ReportError> {
    let mut report = report(skeleton).map_err(ReportError::Network)?;
    report.water_types = water_type_lengths(skeleton, hydro)?;
    report.surface = surface_water(streams);
    report.passages = survey.statistics.clone();
    report.void_volume = Some(survey.void_volume.clone());
    Ok(report)
}

/// The surface streams' length per water type and their falls.
pub fn surface_water(streams: &Streams) -> SurfaceWater {
    let mut water_types: BTreeMap<String, f64> =
        WaterType::ALL.iter().map(|t| (t.name().to_string(), 0.0)).collect();
    for (t, length) in streams.lengths() {
        water_types.insert(t.name().to_string(), length);
    }
    SurfaceWater { water_types, falls: streams.falls() }
}

/// The network of a skeleton as karstnet sees it.
pub fn network_of(skeleton: &Skeleton) -> Network {
    Network {
        nodes: skeleton.nodes.iter().map(|n| n.position).collect(),
        links: skeleton.links().into_iter().map(|[a, b]| [a as usize, b as usize]).collect(),
    }
}

/// The report of a skeleton (karstnet's statistics, zones and conduit types).
pub fn report(skeleton: &Skeleton) -> Result<MetricsReport, crate::MetricsError> {
    let metrics = characterize(&network_of(skeleton))?;
    Ok(MetricsReport {
        karstnet: ranges::compare(&metrics).into_iter().map(|(k, c)| (k.to_string(), c)).collect(),
        network: metrics,
        zones: zone_lengths(skeleton),
        conduit_types: ConduitType::ALL
            .iter()
            .map(|&t| (t.name().to_string(), skeleton.length_of_type(t) + 0.0)) // + 0.0: no -0 for an empty sum
            .collect(),
        water_types: BTreeMap::new(),
        surface: SurfaceWater::default(),
        passages: BTreeMap::new(),
        void_volume: None,
        hints: Vec::new(),
        target: None,
    })
}

/// Conduit length per water type of `hydro`, which must describe the segments of `skeleton`.
pub fn water_type_lengths(skeleton: &Skeleton, hydro: &Hydro) -> Result<BTreeMap<String, f64>, ReportError> {
    let mut lengths: BTreeMap<String, f64> =
        WaterType::ALL.iter().map(|t| (t.name().to_string(), 0.0)).collect();
    if hydro.conduits.len() != skeleton.conduits.len() {
        return Err(ReportError::ConduitCounts {
            hydro: hydro.conduits.len(),
            skeleton: skeleton.conduits.len(),
        });
    }
    for (c, (conduit, water)) in skeleton.conduits.iter().zip(&hydro.conduits).enumerate() {
        if water.segments.len() + 1 != conduit.nodes.len() {
            return Err(ReportError::Segments { conduit: c, segments: water.segments.len() });
        }
        for (w, segment) in conduit.nodes.windows(2).zip(&water.segments) {
            let [a, b] = [w[0], w[1]].map(|i| skeleton.nodes[i as usize].position);
            *lengths.entry(segment.water.name().to_string()).or_default() +=
                crate::geometry::distance(&a, &b);
        }
    }
    Ok(lengths)
}

/// Conduit length per zone; a segment between zones counts half in each.
pub fn zone_lengths(skeleton: &Skeleton) -> ZoneLengths {
    let mut lengths = ZoneLengths { vadose: 0.0, phreatic: 0.0 };
    for conduit in &skeleton.conduits {
        for w in conduit.nodes.windows(2) {
            let [a, b] = [w[0], w[1]].map(|i| &skeleton.nodes[i as usize]);
            let length = crate::geometry::distance(&a.position, &b.position);
            for node in [a, b] {
                match node.zone {
                    Zone::Vadose => lengths.vadose += length / 2.0,
                    Zone::Phreatic => lengths.phreatic += length / 2.0,
                }
            }
        }
    }
    lengths
}

#[cfg(test)]
mod tests {
    use super::*;
    use karst_skeleton::{Conduit, Node};

    fn node(position: [f64; 3], zone: Zone) -> Node {
        Node { position, sample: 0, keypoint: None, zone }
    }

    #[test]
    fn zones_and_types_split_the_total_length() {
        let skeleton = Skeleton {
            nodes: vec![
                node([0.0, 0.0, 10.0], Zone::Vadose),
                node([0.0, 0.0, 0.0], Zone::Vadose),
                node([4.0, 0.0, 0.0], Zone::Phreatic),
                node([4.0, 6.0, 0.0], Zone::Phreatic),
            ],
            conduits: vec![Conduit {
                nodes: vec![0, 1, 2, 3],
                radius: vec![1.0; 4],
                types: vec![ConduitType::Tube, ConduitType::Keyhole, ConduitType::Bed],
                phase: 0,
                keypoints: vec![],
                profile: Vec::new(),
            }],
            routes: vec![],
            derived: Default::default(),
        };
        let r = report(&skeleton).expect("valid");
        assert_eq!(r.zones, ZoneLengths { vadose: 12.0, phreatic: 8.0 });
        assert_eq!(r.conduit_types["tube"], 10.0);
        assert_eq!(r.conduit_types["keyhole"], 4.0);
        assert_eq!(r.conduit_types["bed"], 6.0);
        assert_eq!(r.conduit_types.values().sum::<f64>(), r.network.total_length);
        assert_eq!(r.karstnet.len(), 10);
        assert_eq!(r.karstnet["mean length"].value, 20.0);
    }
}
