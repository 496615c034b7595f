//! The sdf stage's contract: `skeleton.json`, `hydro.json` and `streams.json` in, `sdf.bin`
//! out; `slice` and `sections` draw a model and the cross-section library.

use std::path::PathBuf;

use karst_artifact::{Header, StageId, read_artifact};
use karst_hydro::Hydro;
use karst_skeleton::Skeleton;
use karst_stage::{Stage, StageError};
use karst_streams::Streams;

use crate::build::build;
use crate::error::SdfError;
use crate::field::carved::CarvedTerrain;
use crate::payload::SdfModel;
use crate::slice::{self, Plane};
use crate::view::SdfView;
use crate::water::surface;

/// Stage 6: the signed-distance model of the carved terrain and of the water.
pub struct SdfStage;

impl Stage for SdfStage {
    const ID: StageId = StageId::Sdf;
    type Inputs = (Skeleton, Hydro, Streams);
    type Output = SdfModel;
    type Error = SdfError;
    type View<'s> = SdfView<'s>;

    /// The caves and their water, then the surface water carved into the terrain.
    fn build(
        view: &SdfView,
        (skeleton, hydro, streams): &(Skeleton, Hydro, Streams),
    ) -> Result<SdfModel, SdfError> {
        let mut model = build(view, skeleton, hydro)?;
        surface::add(&mut model, streams, view.streams);
        Ok(model)
    }

    fn headline(_: &SdfView, model: &SdfModel) -> String {
        let counts: Vec<String> = model
            .primitive_counts()
            .iter()
            .filter(|(_, n)| *n > 0)
            .map(|(k, n)| format!("{n} {k}"))
            .collect();
        counts.join(", ")
    }

    fn summary(header: &Header, model: &SdfModel) -> Vec<String> {
        let mut lines = vec![format!("terrain     λ = {:.4}", model.terrain.lipschitz())];
        let counts = model.primitive_counts();
        for (kind, n) in counts {
            lines.push(format!("{kind:<11} {n}"));
        }
        let total: usize = counts.iter().map(|(_, n)| n).sum();
        lines.push(format!(
            "bytes       {} payload ({:.1} per primitive)",
            header.payload_len,
            header.payload_len as f64 / total.max(1) as f64
        ));
        let field = CarvedTerrain::new(model.clone());
        let [karst, water] = field.memory();
        let leaves = field.leaves().max(1) as f64;
        lines.push(format!(
            "memory      {karst} bytes for the karst ({:.1} per karst leaf), {water} for the water ({:.1} per karst leaf with it)",
            karst as f64 / leaves,
            (karst + water) as f64 / leaves
        ));
        lines
    }
}

/// Arguments of `karst-sdf slice`.
#[derive(clap::Args, Debug)]
#[command(group = clap::ArgGroup::new("plane").required(true))]
pub struct SliceArgs {
    /// The sdf.bin to slice.
    pub file: PathBuf,
    /// Horizontal slice at this height (metres).
    #[arg(long, group = "plane")]
    pub z: Option<f64>,
    /// Vertical slice at this northing (metres): cuts east-west conduits across.
    #[arg(long, group = "plane")]
    pub y: Option<f64>,
    /// Vertical slice at this easting (metres): cuts north-south conduits across.
    #[arg(long, group = "plane")]
    pub x: Option<f64>,
    /// Pixel size, metres.
    #[arg(long, default_value_t = 0.5)]
    pub pixel: f64,
    /// Window u0,u1,v0,v1 in the plane's coordinates (default: the domain).
    #[arg(long, value_delimiter = ',', allow_negative_numbers = true)]
    pub window: Option<Vec<f64>>,
    #[arg(long)]
    pub png: Option<PathBuf>,
    #[arg(long)]
    pub exr: Option<PathBuf>,
}

/// `karst-sdf slice`.
pub fn slice(args: &SliceArgs) -> Result<(), StageError> {
    let plane = match (args.z, args.y, args.x) {
        (Some(z), _, _) => Plane::Z(z),
        (None, Some(y), _) => Plane::Y(y),
        (None, None, Some(x)) => Plane::X(x),
        (None, None, None) => return Err(StageError::input("slice: give --z, --y or --x")),
    };
    let at = args.z.or(args.y).or(args.x);
    if !(args.pixel > 0.0 && args.pixel.is_finite() && at.is_some_and(f64::is_finite)) {
        return Err(StageError::input(format!(
            "slice: --pixel {} and the plane must be finite, pixel > 0",
            args.pixel
        )));
    }
    if args.png.is_none() && args.exr.is_none() {
        return Err(StageError::input("slice: give --png FILE and/or --exr FILE"));
    }
    let window = match args.window.as_deref() {
        None => None,
        Some(&[u0, u1, v0, v1]) if [u0, u1, v0, v1].iter().all(|v| v.is_finite()) && u0 < u1 && v0 < v1 => {
            Some([u0, u1, v0, v1])
        }
        Some(w) => {
            return Err(StageError::input(format!("slice: --window {w:?} must be u0 < u1, v0 < v1, finite")));
        }
    };
    let (_, model) = read_artifact::<SdfModel>(&args.file)?;
    let field = CarvedTerrain::new(model);
    let grid = slice::SliceGrid::new(&field, plane, args.pixel, window);
    if let Some(png) = &args.png {
        slice::write_png(&field, &grid, png)
            .map_err(|e| StageError::failure(format!("{}: {e}", png.display())))?;
    }
    if let Some(exr) = &args.exr {
        slice::write_exr(&field, &grid, exr)
            .map_err(|e| StageError::failure(format!("{}: {e}", exr.display())))?;
    }
    Ok(())
}

/// Arguments of `karst-sdf sections`.
#[derive(clap::Args, Debug)]
pub struct SectionsArgs {
    /// Height/width factor (as `sdf.ratio`).
    #[arg(long, default_value_t = 1.0)]
    pub ratio: f64,
    /// Shear of the upper half (as `sdf.asymmetry`).
    #[arg(long, default_value_t = 0.2, allow_negative_numbers = true)]
    pub asymmetry: f64,
    #[arg(long)]
    pub png: PathBuf,
}

/// `karst-sdf sections`: the cross-section library as a picture.
pub fn sections(args: &SectionsArgs) -> Result<(), StageError> {
    if !(args.ratio > 0.0 && args.ratio.is_finite() && args.asymmetry.is_finite()) {
        return Err(StageError::input(format!(
            "sections: --ratio {} must be > 0 and --asymmetry {} finite",
            args.ratio, args.asymmetry
        )));
    }
    slice::write_sections_png(args.ratio, args.asymmetry, 40.0, &args.png)
        .map_err(|e| StageError::failure(format!("{}: {e}", args.png.display())))
}
