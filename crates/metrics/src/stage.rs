//! The metrics stage: `skeleton.json` in, `metrics.json` out.

use std::time::Instant;

use serde::{Deserialize, Serialize};

use karst_artifact::cli::{InspectArgs, RunArgs, StageRun, print_json};
use karst_artifact::{Kind, Payload, Stage, StageError, read_artifact, write_artifact};
use karst_geology::Scene;
use karst_skeleton::Skeleton;

use crate::{Metrics, Network, characterize};

/// The metrics artifact: karstnet's statistics of the network, under karstnet's key names.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct MetricsReport {
    #[serde(flatten)]
    pub metrics: Metrics,
}

impl Payload for MetricsReport {
    const KIND: Kind = Kind::Metrics;
    const SCHEMA: u32 = 1;
}

/// The network of a skeleton as karstnet sees it.
pub fn network_of(skeleton: &Skeleton) -> Network {
    Network {
        nodes: skeleton.nodes.iter().map(|n| n.position).collect(),
        links: skeleton.links().into_iter().map(|[a, b]| [a as usize, b as usize]).collect(),
    }
}

/// `karst-metrics run`.
pub fn run(args: &RunArgs) -> Result<String, StageError> {
    let scene = Scene::load(&args.scene)?;
    let mut run = StageRun::new(Stage::Metrics, &args.out);
    let skeleton: Skeleton = run.read_input(Stage::Skeleton)?;
    let start = Instant::now();
    let metrics =
        characterize(&network_of(&skeleton)).map_err(|e| StageError::input(format!("skeleton.json: {e}")))?;
    let report = MetricsReport { metrics };
    write_artifact(&run.output_path(), &run.provenance(&scene.params_hash(Stage::Metrics)), &report)?;
    let m = &report.metrics;
    Ok(format!(
        "{} nodes, {} edges, {:.0} m, mean branch length {:.1} m in {:.3} s",
        m.n_nodes_full,
        m.n_edges_full,
        m.total_length,
        m.mean_length,
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
    let value = serde_json::to_value(&report.metrics)
        .map_err(|e| StageError::failure(format!("{}: {e}", args.file.display())))?;
    if let Some(map) = value.as_object() {
        for (key, v) in map {
            println!("  {key:<32} {v}");
        }
    }
    Ok(())
}
