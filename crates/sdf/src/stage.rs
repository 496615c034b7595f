//! The sdf stage: skeleton + hydro in, `sdf.bin` out.

use std::time::Instant;

use karst_artifact::cli::{InspectArgs, RunArgs, StageRun, print_json};
use karst_artifact::{Stage, StageError, read_artifact, write_artifact};
use karst_geology::Scene;
use karst_hydro::Hydro;
use karst_skeleton::Skeleton;

use crate::{SdfModel, build};

/// `karst-sdf run`.
pub fn run(args: &RunArgs) -> Result<String, StageError> {
    let scene = Scene::load(&args.scene)?;
    let mut run = StageRun::new(Stage::Sdf, &args.out);
    let skeleton: Skeleton = run.read_input(Stage::Skeleton)?;
    let hydro: Hydro = run.read_input(Stage::Hydro)?;
    let start = Instant::now();
    let model = build::build(&scene, &skeleton, &hydro)?;
    write_artifact(&run.output_path(), &run.provenance(&scene.params_hash(Stage::Sdf)), &model)?;
    Ok(format!("{} capsules in {:.2} s", model.capsules.len(), start.elapsed().as_secs_f64()))
}

/// `karst-sdf inspect`.
pub fn inspect(args: &InspectArgs) -> Result<(), StageError> {
    if args.json {
        return print_json::<SdfModel>(&args.file);
    }
    let (header, model) = read_artifact::<SdfModel>(&args.file)?;
    println!("{}: sdf, schema {}, by {}", args.file.display(), header.schema, header.producer);
    println!("  terrain     λ = {:.4}", model.terrain.lipschitz());
    println!("  capsules    {}", model.capsules.len());
    println!(
        "  bytes       {} payload ({:.1} per primitive)",
        header.payload_len,
        header.payload_len as f64 / model.capsules.len().max(1) as f64
    );
    Ok(())
}
