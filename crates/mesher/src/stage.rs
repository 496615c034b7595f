//! The mesher stage: `sdf.bin` in, `mesh.bin` and `mesh.obj` out.

use std::time::Instant;

use karst_artifact::cli::{InspectArgs, RunArgs, StageRun, print_json};
use karst_artifact::{Stage, StageError, read_artifact, write_artifact};
use karst_geology::Scene;
use karst_sdf::{CarvedTerrain, SdfModel};

use crate::Mesh;
use crate::polygonize::polygonize;

/// Name of the OBJ export in the output folder.
pub const OBJ_NAME: &str = "mesh.obj";

/// `karst-mesher run`.
pub fn run(args: &RunArgs) -> Result<String, StageError> {
    let scene = Scene::load(&args.scene)?;
    let mut run = StageRun::new(Stage::Mesher, &args.out);
    let model: SdfModel = run.read_input(Stage::Sdf)?;
    let start = Instant::now();
    let mesh = polygonize(&CarvedTerrain::new(model), scene.mesher.cell_size);
    write_artifact(&run.output_path(), &run.provenance(&scene.params_hash(Stage::Mesher)), &mesh)?;
    let obj = args.out.join(OBJ_NAME);
    mesh.write_obj(&obj).map_err(|e| StageError::failure(format!("{}: cannot write: {e}", obj.display())))?;
    Ok(format!(
        "{} triangles, {} vertices, {:.1} evaluations per vertex in {:.2} s",
        mesh.triangles.len(),
        mesh.vertices.len(),
        mesh.field_evaluations as f64 / mesh.vertices.len().max(1) as f64,
        start.elapsed().as_secs_f64()
    ))
}

/// `karst-mesher inspect`.
pub fn inspect(args: &InspectArgs) -> Result<(), StageError> {
    if args.json {
        return print_json::<Mesh>(&args.file);
    }
    let (header, mesh) = read_artifact::<Mesh>(&args.file)?;
    println!("{}: mesh, schema {}, by {}", args.file.display(), header.schema, header.producer);
    println!("  triangles    {}", mesh.triangles.len());
    println!("  vertices     {}", mesh.vertices.len());
    println!("  cell size    {} m", mesh.cell_size);
    println!("  area         {:.1} m²", mesh.area());
    println!("  volume       {:.1} m³ of rock", mesh.enclosed_volume());
    println!(
        "  evaluations  {} ({:.1} per vertex)",
        mesh.field_evaluations,
        mesh.field_evaluations as f64 / mesh.vertices.len().max(1) as f64
    );
    Ok(())
}
