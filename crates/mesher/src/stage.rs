//! The mesher stage: `sdf.bin` in; `mesh.bin`, `mesh.obj` and `export/` out.

use std::path::PathBuf;
use std::time::Instant;

use clap::Args;
use glam::DVec3;

use karst_artifact::cli::{InspectArgs, RunArgs, StageRun, print_json};
use karst_artifact::{Stage, StageError, read_artifact, write_artifact};
use karst_geology::{KeyPointKind, Scene};
use karst_sdf::{CarvedTerrain, SdfModel};

use crate::mesh::Surface;
use crate::{Mesh, build, components, export, render, watertight};

/// The sinks and springs of `scene`: the cleanup keeps the air around them even when it is
/// sealed in rock.
pub fn anchors(scene: &Scene) -> Vec<DVec3> {
    scene
        .keypoints
        .iter()
        .filter(|k| matches!(k.kind, KeyPointKind::Sink | KeyPointKind::Spring))
        .map(|k| k.point())
        .collect()
}

/// `karst-mesher run`.
pub fn run(args: &RunArgs) -> Result<String, StageError> {
    let scene = Scene::load(&args.scene)?;
    let mut run = StageRun::new(Stage::Mesher, &args.out);
    let model: SdfModel = run.read_input(Stage::Sdf)?;
    check_lattice(&args.scene, &model, "mesher.cell_size", scene.mesher.cell_size)?;
    let start = Instant::now();
    let anchors = anchors(&scene);
    let params = &scene.mesher;
    let cave_cell = build::cave_cell(&model, params.cell_size, params.cave_cell_size);
    check_lattice(&args.scene, &model, "mesher.cave_cell_size", cave_cell)?;
    let mesh = build::build_simplified(
        &CarvedTerrain::new(model),
        params.cell_size,
        cave_cell,
        &anchors,
        params.target_triangles,
    );
    write_artifact(&run.output_path(), &run.provenance(&scene.params_hash(Stage::Mesher)), &mesh)?;
    export::write_all(&args.out, &mesh)
        .map_err(|e| StageError::failure(format!("{}: cannot write the exports: {e}", args.out.display())))?;
    let (t, c, w) = (&mesh.terrain, &mesh.cave, &mesh.water);
    Ok(format!(
        "terrain {} triangles, cave {} triangles, water {} triangles; removed {} islands and {} \
         pockets; {:.1} evaluations per vertex in {:.2} s",
        t.triangles.len(),
        c.triangles.len(),
        w.triangles.len(),
        t.removed.islands + c.removed.islands,
        t.removed.pockets + c.removed.pockets,
        (t.field_evaluations + c.field_evaluations + w.field_evaluations) as f64
            / (t.vertices.len() + c.vertices.len() + w.vertices.len()).max(1) as f64,
        start.elapsed().as_secs_f64()
    ))
}

/// Cells per axis the lattice may have: lattice point ids are (k·ny + j)·nx + i in a u64.
const MAX_CELLS_PER_AXIS: f64 = (1u64 << 21) as f64;

/// Refuses a cell size that would overflow the lattice's point ids.
fn check_lattice(
    scene: &std::path::Path,
    model: &SdfModel,
    field: &str,
    cell_size: f64,
) -> Result<(), StageError> {
    let cells = (model.domain.size() / cell_size).max_element() + 2.0;
    if cells > MAX_CELLS_PER_AXIS {
        return Err(StageError::input(format!(
            "{}: {field} = {cell_size} gives {cells:.0} cells along the domain's longest axis; \
             at most {MAX_CELLS_PER_AXIS} are possible",
            scene.display()
        )));
    }
    Ok(())
}

/// `karst-mesher inspect`.
pub fn inspect(args: &InspectArgs) -> Result<(), StageError> {
    if args.json {
        return print_json::<Mesh>(&args.file);
    }
    let (header, mesh) = read_artifact::<Mesh>(&args.file)?;
    println!("{}: mesh, schema {}, by {}", args.file.display(), header.schema, header.producer);
    println!("  cell size    {} m (terrain), {} m (cave and water)", mesh.cell_size, mesh.cave_cell_size);
    for (name, surface) in mesh.surfaces() {
        summary(name, surface);
    }
    Ok(())
}

fn summary(name: &str, s: &Surface) {
    println!("  {name}");
    println!("    triangles    {}", s.triangles.len());
    println!("    vertices     {}", s.vertices.len());
    println!("    components   {}", components::count(s));
    match watertight::check(s) {
        Ok(()) => println!("    watertight   yes: closed, 2-manifold, oriented, no degenerate triangle"),
        Err(defect) => println!("    watertight   NO: {defect}"),
    }
    println!("    area         {:.1} m²", s.area());
    println!("    volume       {:.1} m³ enclosed", s.enclosed_volume());
    println!("    evaluations  {} ({:.2} per vertex)", s.field_evaluations, s.evaluations_per_vertex());
    let r = &s.removed;
    println!(
        "    removed      {} islands ({:.1} m³), {} pockets ({:.1} m³)",
        r.islands, r.island_volume, r.pockets, r.pocket_volume
    );
}

/// `karst-mesher render`: a PNG preview of one surface of a mesh artifact.
#[derive(Debug, Args)]
pub struct RenderArgs {
    /// The mesh artifact (mesh.bin).
    pub file: PathBuf,
    /// The PNG to write.
    #[arg(long)]
    pub png: PathBuf,
    /// Which surface: `cave`, `terrain` or `water`.
    #[arg(long, default_value = "cave")]
    pub surface: String,
    /// Picture width and height, pixels.
    #[arg(long, default_value_t = 1200)]
    pub width: u32,
    #[arg(long, default_value_t = 800)]
    pub height: u32,
}

/// `karst-mesher render`.
pub fn render(args: &RenderArgs) -> Result<(), StageError> {
    let (_, mesh) = read_artifact::<Mesh>(&args.file)?;
    let surface = match args.surface.as_str() {
        "cave" => &mesh.cave,
        "terrain" => &mesh.terrain,
        "water" => &mesh.water,
        other => {
            return Err(StageError::input(format!(
                "--surface {other}: expected `cave`, `terrain` or `water`"
            )));
        }
    };
    if !(16..=8192).contains(&args.width) || !(16..=8192).contains(&args.height) {
        return Err(StageError::input(format!(
            "--width {} --height {}: each must be within 16..=8192 pixels",
            args.width, args.height
        )));
    }
    let cell = if args.surface == "terrain" { mesh.cell_size } else { mesh.cave_cell_size };
    let caption = format!("{}: {} triangles at {} m", args.surface, surface.triangles.len(), cell);
    let canvas = render::render(surface, args.width, args.height, &caption);
    canvas
        .write_png(&args.png)
        .map_err(|e| StageError::failure(format!("{}: cannot write: {e}", args.png.display())))
}
