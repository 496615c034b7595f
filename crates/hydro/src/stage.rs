//! The hydro stage's contract: `skeleton.json` in; `hydro.json`, `hydro_nodes.csv` and
//! `hydro_links.csv` out; `render` draws the water types.

use std::path::{Path, PathBuf};

use karst_artifact::{Header, StageId, read_artifact};
use karst_skeleton::Skeleton;
use karst_stage::human::round;
use karst_stage::{Stage, StageError};

use crate::build::build;
use crate::error::HydroError;
use crate::payload::Hydro;
use crate::view::HydroView;
use crate::water::WaterType;
use crate::{export, render};

/// Stage 4: flow, water type and water geometry of every conduit.
pub struct HydroStage;

impl Stage for HydroStage {
    const ID: StageId = StageId::Hydro;
    type Inputs = (Skeleton,);
    type Output = Hydro;
    type Error = HydroError;
    type View<'s> = HydroView<'s>;

    fn build(view: &HydroView, (skeleton,): &(Skeleton,)) -> Result<Hydro, HydroError> {
        build(view, skeleton)
    }

    fn headline(_: &HydroView, hydro: &Hydro) -> String {
        let total: f64 = hydro.springs.iter().map(|s| s.flow).sum();
        let dry = hydro.conduits.iter().filter(|c| c.dry).count();
        let segments = || hydro.conduits.iter().flat_map(|c| &c.segments);
        let falls = segments().filter(|s| s.water.is_free_fall()).count();
        let sumps = segments().filter(|s| s.water == WaterType::Sump).count();
        format!(
            "{} conduits ({dry} dry), {falls} free-fall and {sumps} sump segments, recharge {} m³/s to {} spring(s)",
            hydro.conduits.len(),
            round(total),
            hydro.springs.len()
        )
    }

    fn summary(_: &Header, hydro: &Hydro) -> Vec<String> {
        let max = hydro.conduits.iter().map(|c| c.flow).fold(0.0, f64::max);
        let mut lines = vec![format!(
            "conduits  {} ({} dry), largest flow {} m³/s",
            hydro.conduits.len(),
            hydro.conduits.iter().filter(|c| c.dry).count(),
            round(max)
        )];
        for w in WaterType::ALL {
            let n = hydro.conduits.iter().flat_map(|c| &c.segments).filter(|s| s.water == w).count();
            if n > 0 {
                lines.push(format!("{:<9} {n} segment(s)", w.name()));
            }
        }
        for s in &hydro.sinks {
            lines.push(format!("sink      {}: {} m³/s", s.name, round(s.recharge)));
        }
        for s in &hydro.springs {
            lines.push(format!("spring    {}: {} m³/s", s.name, round(s.flow)));
        }
        lines
    }

    /// `hydro_nodes.csv` and `hydro_links.csv`, for flow models.
    fn side_files(
        out: &Path,
        _: &HydroView,
        (skeleton,): &(Skeleton,),
        hydro: &mut Hydro,
    ) -> std::io::Result<()> {
        export::write(out, skeleton, hydro)
    }
}

/// `karst-hydro render DIR [--png FILE]`.
#[derive(Debug, Clone, clap::Args)]
pub struct RenderArgs {
    /// Folder holding skeleton.json and hydro.json.
    pub dir: PathBuf,
    /// The picture to write; default DIR/hydro.png.
    #[arg(long)]
    pub png: Option<PathBuf>,
}

/// `karst-hydro render`.
pub fn render(args: &RenderArgs) -> Result<(), StageError> {
    let (_, skeleton) = read_artifact::<Skeleton>(&args.dir.join(StageId::Skeleton.file_name()))?;
    let (_, hydro) = read_artifact::<Hydro>(&args.dir.join(StageId::Hydro.file_name()))?;
    if hydro.conduits.len() != skeleton.conduits.len() {
        return Err(StageError::input(format!(
            "{}: describes {} conduits, skeleton.json has {}: rerun the pipeline from hydro",
            args.dir.join(StageId::Hydro.file_name()).display(),
            hydro.conduits.len(),
            skeleton.conduits.len()
        )));
    }
    let png = args.png.clone().unwrap_or_else(|| args.dir.join("hydro.png"));
    render::picture(&skeleton, &hydro)
        .write_png(&png)
        .map_err(|e| StageError::failure(format!("cannot write {}: {e}", png.display())))?;
    println!("{}", png.display());
    Ok(())
}
