//! The costgraph stage: scene + `samples.bin` in, `costgraph.bin` out.

use std::time::Instant;

use karst_artifact::cli::{InspectArgs, RunArgs, StageRun, print_json};
use karst_artifact::{Stage, StageError, read_artifact, write_artifact};
use karst_geology::Scene;
use karst_sampling::Samples;

use crate::{CostGraph, build};

/// `karst-costgraph run`.
pub fn run(args: &RunArgs) -> Result<String, StageError> {
    let scene = Scene::load(&args.scene)?;
    let mut run = StageRun::new(Stage::Costgraph, &args.out);
    let samples: Samples = run.read_input(Stage::Sampling)?;
    let start = Instant::now();
    let graph = build(&scene, &samples)?;
    write_artifact(&run.output_path(), &run.provenance(&scene.params_hash(Stage::Costgraph)), &graph)?;
    Ok(format!(
        "{} nodes, {} edges, {} cost set(s) in {:.2} s",
        graph.node_count(),
        graph.edge_count(),
        graph.cost_sets.len(),
        start.elapsed().as_secs_f64()
    ))
}

/// `karst-costgraph inspect`: counts, memory, and the distribution of edge lengths and of
/// every cost term in every cost set.
pub fn inspect(args: &InspectArgs) -> Result<(), StageError> {
    if args.json {
        return print_json::<CostGraph>(&args.file);
    }
    let (header, graph) = read_artifact::<CostGraph>(&args.file)?;
    let edges = graph.edge_count().max(1) as f64;
    println!("{}: costgraph, schema {}, by {}", args.file.display(), header.schema, header.producer);
    println!("  model     {}", graph.summary.model);
    println!("  nodes     {}", graph.node_count());
    println!("  edges     {} ({:.1} per node)", graph.edge_count(), edges / graph.node_count().max(1) as f64);
    println!(
        "  memory    {} bytes ({:.1} per edge); file payload {} bytes ({:.1} per edge)",
        graph.bytes_in_memory(),
        graph.bytes_in_memory() as f64 / edges,
        header.payload_len,
        header.payload_len as f64 / edges
    );
    if let Some(lengths) = &graph.summary.lengths {
        println!("  length m  {}", lengths.line());
    }
    for set in &graph.summary.sets {
        match &set.water_table {
            Some(w) => println!("  cost set of water table \"{w}\""),
            None => println!("  cost set"),
        }
        for term in &set.terms {
            println!("    {:<17} × {:<6} {}", term.name, term.weight, term.histogram.line());
        }
        println!("    {:<26} {}", "cost per metre", set.cost_per_metre.line());
    }
    Ok(())
}
