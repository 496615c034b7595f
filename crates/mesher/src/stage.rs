//! The mesher stage's contract: `sdf.bin` in, `mesh.bin` out (the export stage writes the
//! meshes in other formats); `render` draws one surface.

use std::path::PathBuf;

use clap::Args;

use karst_artifact::{Header, StageId, read_artifact};
use karst_geology::Scene;
use karst_sdf::SdfModel;
use karst_stage::{Stage, StageError};

use crate::build::build;
use crate::error::MesherError;
use crate::payload::{Mesh, TriMesh};
use crate::{components, render, watertight};

/// Stage 6: watertight meshes of the carved terrain, the cave alone and the water.
pub struct MesherStage;

impl Stage for MesherStage {
    const ID: StageId = StageId::Mesher;
    type Inputs = (SdfModel,);
    type Output = Mesh;
    type Error = MesherError;

    fn build(scene: &Scene, (model,): &(SdfModel,)) -> Result<Mesh, MesherError> {
        build(scene, model)
    }

    fn headline(_: &Scene, mesh: &Mesh) -> String {
        let (t, c, w) = (&mesh.terrain, &mesh.cave, &mesh.water);
        format!(
            "terrain {} triangles, cave {} triangles, water {} triangles; removed {} islands and {} \
             pockets; {:.1} evaluations per vertex",
            t.triangles.len(),
            c.triangles.len(),
            w.triangles.len(),
            t.removed.islands + c.removed.islands,
            t.removed.pockets + c.removed.pockets,
            (t.field_evaluations + c.field_evaluations + w.field_evaluations) as f64
                / (t.vertices.len() + c.vertices.len() + w.vertices.len()).max(1) as f64
        )
    }

    fn summary(_: &Header, mesh: &Mesh) -> Vec<String> {
        let mut lines = vec![format!(
            "cell size    {} m (terrain), {} m (cave and water)",
            mesh.cell_size, mesh.cave_cell_size
        )];
        for (name, surface) in mesh.surfaces() {
            lines.extend(surface_summary(name, surface));
        }
        lines
    }
}

fn surface_summary(name: &str, s: &TriMesh) -> Vec<String> {
    let mut lines = vec![name.to_string()];
    lines.push(format!("  triangles    {}", s.triangles.len()));
    lines.push(format!("  vertices     {}", s.vertices.len()));
    lines.push(format!("  components   {}", components::count(s)));
    lines.push(match watertight::check(s) {
        Ok(()) => "  watertight   yes: closed, 2-manifold, oriented, no degenerate triangle".to_string(),
        Err(defect) => format!("  watertight   NO: {defect}"),
    });
    lines.push(format!("  area         {:.1} m²", s.area()));
    lines.push(format!("  volume       {:.1} m³ enclosed", s.enclosed_volume()));
    lines.push(format!(
        "  evaluations  {} ({:.2} per vertex)",
        s.field_evaluations,
        s.evaluations_per_vertex()
    ));
    let r = &s.removed;
    lines.push(format!(
        "  removed      {} islands ({:.1} m³), {} pockets ({:.1} m³)",
        r.islands, r.island_volume, r.pockets, r.pocket_volume
    ));
    lines
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
    if surface.triangles.is_empty() {
        return Err(StageError::input(format!(
            "{}: the {} surface is empty: nothing to draw",
            args.file.display(),
            args.surface
        )));
    }
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
