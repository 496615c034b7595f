//! The metrics stage: `skeleton.json` and `hydro.json` in, `metrics.json` and three pictures
//! (DIR/preview/) out.
//!
//! `metrics.json` holds, under karstnet's key names, every `characterize_graph()` metric beside
//! its real-cave range (`karstnet`), every statistic of [`Metrics`] (`network`), and what only a
//! karstgen skeleton knows: the conduit length above and below the water table (`zones`) and per
//! conduit type (`conduit_types`, Paris et al. 2021 §5.3). A segment whose two nodes lie in
//! different zones crosses the water table somewhere between them: half of its length counts in
//! each zone.
//!
//! The length per water type (`water_types`: stream, rapid, plunge, sump, pool, dry... of the
//! hydro stage, Emilien et al. 2015 Table 1) sums each segment under the type hydro gave it.

use std::collections::BTreeMap;
use std::path::Path;
use std::time::Instant;

use serde::{Deserialize, Serialize};

use karst_artifact::cli::{InspectArgs, RunArgs, StageRun, print_json};
use karst_artifact::{Kind, Payload, Stage, StageError, read_artifact, write_artifact};
use karst_geology::Scene;
use karst_hydro::{Hydro, WaterType};
use karst_skeleton::{ConduitType, Skeleton, Zone};

use crate::ranges::{self, Compared};
use crate::{Metrics, Network, characterize, distributions, plots};

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
}

/// Conduit length above (vadose) and below (phreatic) the water table, metres.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct ZoneLengths {
    pub vadose: f64,
    pub phreatic: f64,
}

impl Payload for MetricsReport {
    const KIND: Kind = Kind::Metrics;
    const SCHEMA: u32 = 3;
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
    })
}

/// Conduit length per water type of `hydro`, which must describe the segments of `skeleton`.
pub fn water_type_lengths(skeleton: &Skeleton, hydro: &Hydro) -> Result<BTreeMap<String, f64>, String> {
    let mut lengths: BTreeMap<String, f64> =
        WaterType::ALL.iter().map(|t| (t.name().to_string(), 0.0)).collect();
    if hydro.conduits.len() != skeleton.conduits.len() {
        return Err(format!(
            "hydro.json has {} conduits, skeleton.json {}",
            hydro.conduits.len(),
            skeleton.conduits.len()
        ));
    }
    for (c, (conduit, water)) in skeleton.conduits.iter().zip(&hydro.conduits).enumerate() {
        if water.segments.len() + 1 != conduit.nodes.len() {
            return Err(format!("conduit {c}: hydro.json has {} segments", water.segments.len()));
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

/// Writes the rose diagram, the branch-length histogram and the range chart of a network.
pub fn write_plots(dir: &Path, net: &Network, metrics: &Metrics) -> Result<(), StageError> {
    let d = distributions(net).map_err(|e| StageError::input(e.to_string()))?;
    plots::write_all(dir, &d.azimuth_lengths, &d.branch_lengths, &ranges::compare(metrics))
        .map_err(|e| StageError::failure(format!("{}: cannot write the plots: {e}", dir.display())))
}

/// `karst-metrics run`.
pub fn run(args: &RunArgs) -> Result<String, StageError> {
    let scene = Scene::load(&args.scene)?;
    let mut run = StageRun::new(Stage::Metrics, &args.out);
    let skeleton: Skeleton = run.read_input(Stage::Skeleton)?;
    let hydro: Hydro = run.read_input(Stage::Hydro)?;
    let start = Instant::now();
    let mut report = report(&skeleton).map_err(|e| StageError::input(format!("skeleton.json: {e}")))?;
    report.water_types = water_type_lengths(&skeleton, &hydro)
        .map_err(|e| StageError::input(format!("{e}: rerun `cargo xtask run --from hydro`")))?;
    write_artifact(&run.output_path(), &run.provenance(&scene.params_hash(Stage::Metrics)), &report)?;
    write_plots(&args.out.join("preview"), &network_of(&skeleton), &report.network)?;
    let m = &report.network;
    let inside = report.karstnet.values().filter(|c| c.inside).count();
    Ok(format!(
        "{} nodes, {} branches, {:.0} m, {inside}/{} metrics within real caves, in {:.3} s",
        m.n_nodes_full,
        m.n_branches,
        m.total_length,
        report.karstnet.len(),
        start.elapsed().as_secs_f64()
    ))
}

/// `karst-metrics inspect`.
pub fn inspect(args: &InspectArgs) -> Result<(), StageError> {
    if args.json {
        return print_json::<MetricsReport>(&args.file);
    }
    let (header, report) = read_artifact::<MetricsReport>(&args.file)?;
    println!("{}: metrics, schema {}, by {}", args.file.display(), header.schema, header.producer);
    for (key, c) in &report.karstnet {
        let verdict = if c.inside { "inside" } else { "OUTSIDE" };
        let r = &c.real_caves;
        println!("  {key:<28} {:>12.5}  {verdict:<7} [{:.4}, {:.4}]", c.value, r.min, r.max);
    }
    for (key, value) in report.network.to_pairs().into_iter().skip(ranges::CHARACTERIZE_KEYS.len()) {
        println!("  {key:<28} {value:>12.5}");
    }
    println!("  vadose length {:.1} m, phreatic length {:.1} m", report.zones.vadose, report.zones.phreatic);
    for (kind, length) in report.conduit_types.iter().chain(&report.water_types).filter(|(_, l)| **l > 0.0) {
        println!("  {kind} {length:.1} m");
    }
    Ok(())
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
            }],
            routes: vec![],
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
