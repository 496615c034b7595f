//! The hydro stage: `skeleton.json` in, `hydro.json` out.

use std::time::Instant;

use karst_artifact::cli::{InspectArgs, RunArgs, StageRun, print_json};
use karst_artifact::{Stage, StageError, read_artifact, write_artifact};
use karst_geology::Scene;
use karst_skeleton::Skeleton;

use crate::{Hydro, flow};

/// `karst-hydro run`.
pub fn run(args: &RunArgs) -> Result<String, StageError> {
    let scene = Scene::load(&args.scene)?;
    let mut run = StageRun::new(Stage::Hydro, &args.out);
    let skeleton: Skeleton = run.read_input(Stage::Skeleton)?;
    let start = Instant::now();
    let hydro = flow::compute(&skeleton);
    write_artifact(&run.output_path(), &run.provenance(&scene.params_hash(Stage::Hydro)), &hydro)?;
    let total: f64 = hydro.springs.iter().map(|s| s.flow).sum();
    let dry = hydro.conduits.iter().filter(|c| c.dry).count();
    Ok(format!(
        "{} conduits ({dry} dry), {total} flow units to {} spring(s) in {:.2} s",
        hydro.conduits.len(),
        hydro.springs.len(),
        start.elapsed().as_secs_f64()
    ))
}

/// `karst-hydro inspect`.
pub fn inspect(args: &InspectArgs) -> Result<(), StageError> {
    if args.json {
        return print_json::<Hydro>(&args.file);
    }
    let (header, hydro) = read_artifact::<Hydro>(&args.file)?;
    let max = hydro.conduits.iter().map(|c| c.flow).fold(0.0, f64::max);
    println!("{}: hydro, schema {}, by {}", args.file.display(), header.schema, header.producer);
    println!(
        "  conduits  {} ({} dry), largest flow {max}",
        hydro.conduits.len(),
        hydro.conduits.iter().filter(|c| c.dry).count()
    );
    for s in &hydro.sinks {
        println!("  sink      {}: {}", s.name, s.flow);
    }
    for s in &hydro.springs {
        println!("  spring    {}: {}", s.name, s.flow);
    }
    Ok(())
}
