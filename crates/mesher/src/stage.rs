//! The mesher stage's contract: `sdf.bin` in, `mesh.bin` out (the export stage writes the
//! meshes in other formats); `render` draws one surface.

use std::path::PathBuf;

use clap::Args;

use karst_artifact::{Header, StageId, read_artifact};
use karst_sdf::SdfModel;
use karst_stage::{ArtifactOut, Stage, StageError, Written};

use crate::build::{build, write_streamed};
use crate::error::MesherError;
use crate::payload::{Mesh, SurfaceCounts, TriMesh};
use crate::view::MesherView;
use crate::{components, render, watertight};

/// Stage 7: watertight meshes of the carved terrain, the cave alone and the water.
pub struct MesherStage;

impl Stage for MesherStage {
    const ID: StageId = StageId::Mesher;
    type Inputs = (SdfModel,);
    type Output = Mesh;
    type Error = MesherError;
    type View<'s> = MesherView<'s>;

    fn build(view: &MesherView, (model,): &(SdfModel,)) -> Result<Mesh, MesherError> {
        build(view, model)
    }

    fn headline(_: &MesherView, mesh: &Mesh) -> String {
        headline([&mesh.terrain, &mesh.cave, &mesh.water].map(SurfaceCounts::from))
    }

    /// Streamed unless the scene simplifies its surfaces ([`crate::build::write_streamed`]).
    fn write_streamed(
        view: &MesherView,
        (model,): &(SdfModel,),
        artifact: &mut ArtifactOut<'_, Mesh>,
    ) -> Option<Result<Written, MesherError>> {
        if view.mesher.target_triangles > 0 {
            return None;
        }
        Some(
            write_streamed(view, model, artifact)
                .map(|counts| Written { headline: headline(counts), notes: Vec::new() }),
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

/// The run's headline: triangles per surface, what the cleanup removed, evaluations per vertex.
fn headline([t, c, w]: [SurfaceCounts; 3]) -> String {
    format!(
        "terrain {} triangles, cave {} triangles, water {} triangles; removed {} islands and {} \
         pockets; {:.1} evaluations per vertex",
        t.triangles,
        c.triangles,
        w.triangles,
        t.removed.islands + c.removed.islands,
        t.removed.pockets + c.removed.pockets,
        (t.field_evaluations + c.field_evaluations + w.field_evaluations) as f64
            / (t.vertices + c.vertices + w.vertices).max(1) as f64
    )
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
    /// Which surface: `cave`, `terrain` or `water`; or two joined by `+` (`terrain+water`): the
    /// first tinted by elevation, the second in blue over it.
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
    let pick = |name: &str| match name {
        "cave" => Ok(&mesh.cave),
        "terrain" => Ok(&mesh.terrain),
        "water" => Ok(&mesh.water),
        other => Err(StageError::input(format!(
            "--surface {other}: expected `cave`, `terrain` or `water`, or two of them joined by `+`"
        ))),
    };
    let names: Vec<&str> = args.surface.split('+').collect();
    if names.len() > 2 {
        return Err(StageError::input(format!("--surface {}: at most two surfaces", args.surface)));
    }
    let surface = pick(names[0])?;
    let over = names.get(1).map(|n| pick(n)).transpose()?;
    if surface.triangles.is_empty() {
        return Err(StageError::input(format!(
            "{}: the {} surface is empty: nothing to draw",
            args.file.display(),
            names[0]
        )));
    }
    if !(16..=8192).contains(&args.width) || !(16..=8192).contains(&args.height) {
        return Err(StageError::input(format!(
            "--width {} --height {}: each must be within 16..=8192 pixels",
            args.width, args.height
        )));
    }
    let cell = |name: &str| if name == "terrain" { mesh.cell_size } else { mesh.cave_cell_size };
    let described: Vec<String> = names
        .iter()
        .map(|&n| {
            let triangles = pick(n).map_or(0, |s| s.triangles.len());
            format!("{n} {triangles} triangles at {} m", karst_stage::human::round(cell(n)))
        })
        .collect();
    let caption = described.join(", ");
    let others: Vec<(&TriMesh, glam::DVec3)> = over.into_iter().map(|s| (s, render::WATER)).collect();
    let canvas = render::render(surface, &others, args.width, args.height, &caption);
    canvas
        .write_png(&args.png)
        .map_err(|e| StageError::failure(format!("{}: cannot write: {e}", args.png.display())))
}
