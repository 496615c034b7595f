//! The skeleton stage: scene + samples + costgraph in, `skeleton.json` (and karstnet's
//! `network_nodes.dat` / `network_links.dat`) out.

use std::time::Instant;

use karst_artifact::cli::{InspectArgs, RunArgs, StageRun, print_json};
use karst_artifact::{Stage, StageError, read_artifact, write_artifact};
use karst_costgraph::CostGraph;
use karst_geology::Scene;
use karst_geology::params::SkeletonMode;
use karst_sampling::Samples;

use crate::{ConduitType, Skeleton, Zone, karstnet, routing};

/// Base name of the karstnet export inside the output folder.
pub const KARSTNET_BASE: &str = "network";

/// `karst-skeleton run`.
pub fn run(args: &RunArgs) -> Result<String, StageError> {
    let scene = Scene::load(&args.scene)?;
    let mut run = StageRun::new(Stage::Skeleton, &args.out);
    let samples: Samples = run.read_input(Stage::Sampling)?;
    let graph: CostGraph = run.read_input(Stage::Costgraph)?;
    if graph.node_count() != samples.len() {
        return Err(StageError::input(format!(
            "costgraph.bin has {} nodes but samples.bin has {} samples: rerun `cargo xtask run --from costgraph`",
            graph.node_count(),
            samples.len()
        )));
    }
    let start = Instant::now();
    let skeleton = routing::build(&scene, &samples, &graph)?;
    write_artifact(&run.output_path(), &run.provenance(&scene.params_hash(Stage::Skeleton)), &skeleton)?;
    karstnet::write(&skeleton, &args.out.join(KARSTNET_BASE)).map_err(|e| {
        StageError::failure(format!("{}: cannot write the karstnet export: {e}", args.out.display()))
    })?;
    // Least-cost distances obey the triangle inequality, so γ ≤ 1 prunes nothing (docs/skeleton.md):
    // say so, since Paris et al.'s Table 1 suggests 0.8 for mazes.
    let complete = scene.skeleton.mode == SkeletonMode::Gamma && scene.skeleton.gamma <= 1.0;
    Ok(format!(
        "{} nodes, {} conduits, {:.0} m in {:.2} s{}",
        skeleton.nodes.len(),
        skeleton.conduits.len(),
        skeleton.total_length(),
        start.elapsed().as_secs_f64(),
        if complete { " (skeleton.gamma ≤ 1 keeps every pair of key points)" } else { "" }
    ))
}

/// `karst-skeleton render FILE --png PNG`.
#[derive(Debug, Clone, clap::Args)]
pub struct RenderArgs {
    /// The skeleton artifact.
    pub file: std::path::PathBuf,
    /// The picture to write.
    #[arg(long)]
    pub png: std::path::PathBuf,
    /// Title written on the picture (default: the artifact's file name).
    #[arg(long)]
    pub title: Option<String>,
}

/// `karst-skeleton render`.
pub fn render(args: &RenderArgs) -> Result<(), StageError> {
    let (_, skeleton) = read_artifact::<Skeleton>(&args.file)?;
    let title = args.title.clone().unwrap_or_else(|| args.file.display().to_string());
    crate::render::render(&skeleton, &title)
        .write_png(&args.png)
        .map_err(|e| StageError::failure(format!("{}: cannot write the picture: {e}", args.png.display())))
}

/// `karst-skeleton inspect`.
pub fn inspect(args: &InspectArgs) -> Result<(), StageError> {
    if args.json {
        return print_json::<Skeleton>(&args.file);
    }
    let (header, skeleton) = read_artifact::<Skeleton>(&args.file)?;
    let phreatic = skeleton.nodes.iter().filter(|n| n.zone == Zone::Phreatic).count();
    println!("{}: skeleton, schema {}, by {}", args.file.display(), header.schema, header.producer);
    println!(
        "  nodes     {} ({} vadose, {phreatic} phreatic)",
        skeleton.nodes.len(),
        skeleton.nodes.len() - phreatic
    );
    println!("  conduits  {}", skeleton.conduits.len());
    println!("  length    {:.1} m", skeleton.total_length());
    for kind in ConduitType::ALL {
        let length = skeleton.length_of_type(kind);
        if length > 0.0 {
            println!("  {:<9} {length:.1} m", kind.name());
        }
    }
    for route in &skeleton.routes {
        println!(
            "  route     {} → {}: {} nodes, cost {:.1}",
            route.sink,
            route.spring,
            route.nodes.len(),
            route.cost
        );
    }
    Ok(())
}
