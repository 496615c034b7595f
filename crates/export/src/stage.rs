//! The export stage's contract: every upstream artifact in, the scene's `[export]` formats
//! written into `export/` and their manifest into `export.json`; and exports of any run on
//! demand (`karstgen export DIR --format …`).

use std::path::{Path, PathBuf};

use karst_artifact::{Header, Payload, StageId, check_frame, read_artifact};
use karst_hydro::Hydro;
use karst_mesher::Mesh;
use karst_metrics::MetricsReport;
use karst_sampling::Samples;
use karst_scene::Scene;
use karst_scene::budget::bytes;
use karst_scene::output_budget::OutputBudget;
use karst_skeleton::Skeleton;
use karst_stage::{Stage, StageError};
use karst_streams::Streams;

use crate::build::{FOLDER, Input, Inputs, export, needs};
use crate::error::ExportError;
use crate::estimate::{Counts, Estimate, raster_pixels};
use crate::network::NetworkView;
use crate::payload::Manifest;
use crate::view::ExportView;
use crate::{ExportFormat, ExportParams};

/// The upstream payloads of the export stage.
type Upstream = (Samples, Skeleton, Hydro, Streams, Mesh, MetricsReport);

/// Stage 9: the run in the formats other tools read.
pub struct ExportStage;

impl Stage for ExportStage {
    const ID: StageId = StageId::Export;
    type Inputs = Upstream;
    type Output = Manifest;
    type Error = ExportError;
    type View<'s> = ExportView<'s>;

    /// Checks that the artifacts belong together; the files are written with the side files.
    fn build(_: &ExportView, (_, skeleton, hydro, ..): &Upstream) -> Result<Manifest, ExportError> {
        NetworkView::new(skeleton, hydro)?;
        Ok(Manifest::default())
    }

    fn headline(_: &ExportView, manifest: &Manifest) -> String {
        let bytes: u64 = manifest.files.iter().map(|f| f.bytes).sum();
        format!("{} files, {:.1} MB in {FOLDER}/", manifest.files.len(), bytes as f64 / 1e6)
    }

    fn summary(_: &Header, manifest: &Manifest) -> Vec<String> {
        manifest.files.iter().map(|f| format!("{:<14} {:>12} bytes  {}", f.format, f.bytes, f.name)).collect()
    }

    /// The scene's formats into `export/`, recorded in the manifest; files of the previous
    /// export that this one no longer writes are removed.
    fn side_files(
        out: &Path,
        view: &ExportView,
        upstream: &Upstream,
        manifest: &mut Manifest,
    ) -> std::io::Result<()> {
        let (samples, skeleton, hydro, streams, mesh, metrics) = upstream;
        let inputs = Inputs {
            skeleton: Some(skeleton),
            hydro: Some(hydro),
            streams: Some(streams),
            mesh: Some(mesh),
            metrics: Some(metrics),
            samples: Some(samples),
            geology: Some(view.geology),
            keypoints: Some(view.keypoints),
            terrain: Some(view.terrain),
            domain: Some(view.domain),
            frame: view.frame,
        };
        // The last export's manifest: moved aside by the runner when this export differs.
        let file = out.join(StageId::Export.file_name());
        let previous = [karst_stage::runner::previous_artifact(&file), file]
            .iter()
            .find_map(|path| read_artifact::<Manifest>(path).ok())
            .map(|(_, m)| m);
        *manifest = export(&inputs, view.export, out).map_err(std::io::Error::other)?;
        for stale in previous
            .iter()
            .flat_map(|p| &p.files)
            .filter(|f| !manifest.files.iter().any(|n| n.name == f.name))
        {
            let _ = std::fs::remove_file(out.join(FOLDER).join(&stale.name));
        }
        Ok(())
    }
}

/// `karstgen export DIR [--format a,b] [--scene SCENE] [--json] [--budget MB]`.
#[derive(Debug, Clone, clap::Args)]
pub struct ExportArgs {
    /// The run's output folder (holding skeleton.json, hydro.json, streams.json, mesh.bin, ...).
    pub dir: PathBuf,
    /// Comma-separated formats: vtk, vtk-meshes, gocad, gocad-meshes, survex, swmm, gltf, obj,
    /// ply, csv, gpkg, geotiff (default: the scene's [export] formats, or the cheap ones; gpkg
    /// and geotiff are always added for a scene with a crs).
    #[arg(long, value_delimiter = ',')]
    pub format: Vec<String>,
    /// The scene: its [export] section, and the rock layers of the samples (default: the scene
    /// the run was made from).
    #[arg(long)]
    pub scene: Option<PathBuf>,
    /// Print the manifest (name, format, bytes, blake3 of every file) as JSON.
    #[arg(long)]
    pub json: bool,
    /// The bytes the exports may take with the run's mesh.bin, MB (MiB; default 300, as for
    /// `karstgen run`): beyond it nothing is written.
    #[arg(long, value_name = "MB")]
    pub budget: Option<OutputBudget>,
}

/// Writes the exports of the run in `args.dir` on demand, reading only the artifacts the
/// chosen formats need; the run's artifacts are never touched.
pub fn export_run(args: &ExportArgs) -> Result<(), StageError> {
    if !args.dir.is_dir() {
        return Err(StageError::input(format!(
            "{}: no such folder: give the output folder of a run (`karstgen run SCENE --out DIR`)",
            args.dir.display()
        )));
    }
    // A run writing into the folder meanwhile would change what is exported; another export
    // would write the same files.
    let _lock = karst_artifact::lock_output(&args.dir)?;
    karst_artifact::atomic::remove_stale_temporaries(&args.dir);
    let scene_path = args.scene.clone().or_else(|| karst_stage::run_dir::scene_of(&args.dir));
    let scene = scene_path.as_deref().map(Scene::load).transpose()?;
    let mut params = scene.as_ref().map_or_else(ExportParams::default, |s| s.export().clone());
    if !args.format.is_empty() {
        params.formats = args.format.iter().map(|f| parse_format(f)).collect::<Result<_, _>>()?;
    }
    // The scene's frame decides whether the GIS formats are added; without a scene they
    // cannot be written (they need its key points and terrain).
    let chosen =
        crate::build::formats(&params, scene.as_ref().map(|s| s.frame()).unwrap_or(&Default::default()));
    let wanted = |input: Input| chosen.iter().find(|f| needs(**f).contains(&input)).copied();
    // Every artifact read must be in one frame: the scene's when one is known, else the first's.
    let frame = std::cell::RefCell::new(scene.as_ref().map(|s| s.frame().clone()));
    let read = |input: Input| -> Result<Option<Box<dyn std::any::Any>>, StageError> {
        let Some(format) = wanted(input).filter(|_| input != Input::Scene) else { return Ok(None) };
        let path = args.dir.join(input.file_name());
        if !path.exists() {
            return Err(StageError::input(format!(
                "format `{}` needs {}, which {} lacks: run the stages that write it first (`karstgen run`)",
                format.name(),
                input.file_name(),
                args.dir.display()
            )));
        }
        let (header, payload) = match input {
            Input::Skeleton => load::<Skeleton>(&path)?,
            Input::Hydro => load::<Hydro>(&path)?,
            Input::Streams => load::<Streams>(&path)?,
            Input::Mesh => load::<Mesh>(&path)?,
            Input::Metrics => load::<MetricsReport>(&path)?,
            Input::Samples => load::<Samples>(&path)?,
            Input::Scene => unreachable!("the scene is no artifact"),
        };
        let mut frame = frame.borrow_mut();
        match frame.as_ref() {
            Some(expected) => check_frame(&path, &header, expected)?,
            None => *frame = Some(header.frame()),
        }
        Ok(Some(payload))
    };
    let (skeleton, hydro, streams) = (read(Input::Skeleton)?, read(Input::Hydro)?, read(Input::Streams)?);
    let mesh = read(Input::Mesh)?;
    let (metrics, samples) = (read(Input::Metrics)?, read(Input::Samples)?);
    let frame = frame.into_inner().unwrap_or_default();
    let inputs = Inputs {
        skeleton: skeleton.as_deref().and_then(|a| a.downcast_ref()),
        hydro: hydro.as_deref().and_then(|a| a.downcast_ref()),
        streams: streams.as_deref().and_then(|a| a.downcast_ref()),
        mesh: mesh.as_deref().and_then(|a| a.downcast_ref()),
        metrics: metrics.as_deref().and_then(|a| a.downcast_ref()),
        samples: samples.as_deref().and_then(|a| a.downcast_ref()),
        geology: scene.as_ref().map(Scene::geology),
        keypoints: scene.as_ref().map(|s| &s.keypoints()[..]),
        terrain: scene.as_ref().map(Scene::terrain),
        domain: scene.as_ref().map(Scene::domain),
        frame: &frame,
    };
    // Said before a file is written, and held against the budget as the run does.
    let counts = Counts::of(inputs.skeleton, inputs.samples, inputs.streams, inputs.mesh, &params.surfaces);
    let extent = inputs.domain.map_or([0.0; 2], |d| [0, 1].map(|a| d.max[a] - d.min[a]));
    let mesh_bytes = std::fs::metadata(args.dir.join(Input::Mesh.file_name())).map_or(0, |m| m.len()) as f64;
    let estimate =
        Estimate::of(&chosen, &counts, &params, raster_pixels(extent, params.raster_cell), mesh_bytes);
    let budget = args.budget.unwrap_or_default().bytes;
    if estimate.total() > budget {
        return Err(StageError::input(format!(
            "{}: the export would write {estimate}, more than the budget of {}: choose fewer formats \
             (--format, export.formats) or surfaces (export.surfaces), lower export.gltf_max_mb, or \
             give --budget MB to allow it",
            args.dir.display(),
            bytes(budget)
        )));
    }
    eprintln!("{:<10} estimate    {estimate} (budget {})", "export", bytes(budget));
    // Every failure here is about the user's folder or files, an unwritable path included.
    let manifest = export(&inputs, &params, &args.dir).map_err(StageError::input)?;
    if args.json {
        let text = serde_json::to_string_pretty(&manifest).map_err(|e| StageError::failure(e.to_string()))?;
        println!("{text}");
    } else {
        for f in &manifest.files {
            println!(
                "{:<14} {:>12} bytes  {}",
                f.format,
                f.bytes,
                args.dir.join(FOLDER).join(&f.name).display()
            );
        }
    }
    Ok(())
}

fn parse_format(name: &str) -> Result<ExportFormat, StageError> {
    ExportFormat::from_name(name.trim()).ok_or_else(|| {
        let known: Vec<&str> = ExportFormat::ALL.iter().map(|f| f.name()).collect();
        StageError::input(format!("--format: unknown format `{name}` (known: {})", known.join(", ")))
    })
}

type Loaded = (Header, Box<dyn std::any::Any>);

fn load<P: Payload + 'static>(path: &Path) -> Result<Loaded, StageError> {
    let (header, payload) = read_artifact::<P>(path)?;
    Ok((header, Box::new(payload)))
}
