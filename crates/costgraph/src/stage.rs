//! The costgraph stage: scene + `samples.bin` in, `costgraph.bin` out.

use std::time::Instant;

use glam::DVec3;
use rayon::prelude::*;

use karst_artifact::cli::{InspectArgs, RunArgs, StageRun, print_json};
use karst_artifact::{Stage, StageError, read_artifact, write_artifact};
use karst_geology::Scene;
use karst_sampling::Samples;

use crate::{CostGraph, CostModel, knn};

/// Builds the cost graph of `samples` under `scene`'s geology.
pub fn build(scene: &Scene, samples: &Samples) -> Result<CostGraph, StageError> {
    let k = scene.costgraph.k;
    if k >= samples.len() {
        return Err(StageError::input(format!(
            "costgraph.k = {k} needs more than {k} samples, samples.bin has {}: lower k or sampling.radius",
            samples.len()
        )));
    }
    let model = CostModel::from_scene(scene);
    let lists = knn::neighbours(&samples.positions, k, scene.costgraph.max_edge_length);
    if let Some((i, keypoint)) = lists
        .iter()
        .enumerate()
        .take(scene.keypoints.len())
        .find(|(_, l)| l.is_empty())
        .map(|(i, _)| (i, &scene.keypoints[i]))
    {
        return Err(StageError::input(format!(
            "key point \"{}\" (sample {i}) has no neighbour within costgraph.max_edge_length = {:?}",
            keypoint.name, scene.costgraph.max_edge_length
        )));
    }
    let at = |i: u32| DVec3::from_array(samples.positions[i as usize]);
    let costed: Vec<Vec<(u32, f32)>> = lists
        .into_par_iter()
        .enumerate()
        .map(|(i, list)| {
            list.into_iter().map(|(j, _)| (j, model.edge_cost(at(i as u32), at(j)) as f32)).collect()
        })
        .collect();
    Ok(CostGraph::from_lists(costed))
}

/// `karst-costgraph run`.
pub fn run(args: &RunArgs) -> Result<String, StageError> {
    let scene = Scene::load(&args.scene)?;
    let mut run = StageRun::new(Stage::Costgraph, &args.out);
    let samples: Samples = run.read_input(Stage::Sampling)?;
    let start = Instant::now();
    let graph = build(&scene, &samples)?;
    write_artifact(&run.output_path(), &run.provenance(&scene.params_hash(Stage::Costgraph)), &graph)?;
    Ok(format!(
        "{} nodes, {} edges in {:.2} s",
        graph.node_count(),
        graph.edge_count(),
        start.elapsed().as_secs_f64()
    ))
}

/// `karst-costgraph inspect`: counts and the distribution of edge costs per metre.
pub fn inspect(args: &InspectArgs) -> Result<(), StageError> {
    if args.json {
        return print_json::<CostGraph>(&args.file);
    }
    let (header, graph) = read_artifact::<CostGraph>(&args.file)?;
    println!("{}: costgraph, schema {}, by {}", args.file.display(), header.schema, header.producer);
    println!("  nodes   {}", graph.node_count());
    println!(
        "  edges   {} ({:.1} per node)",
        graph.edge_count(),
        graph.edge_count() as f64 / graph.node_count().max(1) as f64
    );
    println!(
        "  bytes   {} payload ({:.1} per edge)",
        header.payload_len,
        header.payload_len as f64 / graph.edge_count().max(1) as f64
    );
    let mut costs = graph.costs.clone();
    costs.sort_by(f32::total_cmp);
    if !costs.is_empty() {
        let q = |f: f64| costs[((costs.len() - 1) as f64 * f) as usize];
        println!("  cost    min {:.3}  median {:.3}  p90 {:.3}  max {:.3}", q(0.0), q(0.5), q(0.9), q(1.0));
    }
    Ok(())
}
