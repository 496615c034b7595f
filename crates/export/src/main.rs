//! `karst-export DIR [--format vtk,gocad,...] [--scene SCENE] [--json]`: writes the exports of
//! the run in DIR into DIR/export/ (docs/exports.md), reading only the artifacts the chosen
//! formats need. The formats come from `--format`, else from the scene's `[export]` section,
//! else the defaults. Exit code 2 for an unknown format, an input the run lacks or a folder
//! that cannot be written; the run's artifacts are never touched.

use std::path::{Path, PathBuf};
use std::process::ExitCode;

use clap::Parser;

use karst_artifact::cli::{default_sigpipe, finish};
use karst_artifact::{Payload, StageError, read_artifact};
use karst_export::{ExportFormat, ExportParams, Input, Inputs, export, needs};
use karst_geology::Scene;

/// Exports a karstgen run for ParaView, GOCAD, Survex, EPA SWMM, glTF viewers and spreadsheets.
#[derive(Parser)]
#[command(name = "karst-export", version)]
struct Cli {
    /// The run's output folder (holding skeleton.json, hydro.json, mesh.bin, ...).
    dir: PathBuf,
    /// Comma-separated formats: vtk, vtk-meshes, gocad, gocad-meshes, survex, swmm, gltf, obj,
    /// ply, csv (default: the scene's [export] formats, or the cheap ones).
    #[arg(long, value_delimiter = ',')]
    format: Vec<String>,
    /// The scene: its [export] section, and the rock layers of the samples.
    #[arg(long)]
    scene: Option<PathBuf>,
    /// Print the manifest (name, format, bytes, blake3 of every file) as JSON.
    #[arg(long)]
    json: bool,
}

fn main() -> ExitCode {
    default_sigpipe();
    finish(run(&Cli::parse()))
}

fn run(cli: &Cli) -> Result<(), StageError> {
    let scene = cli.scene.as_deref().map(Scene::load).transpose()?;
    let mut params = scene.as_ref().map_or_else(ExportParams::default, |s| s.export.clone());
    if !cli.format.is_empty() {
        params.formats = cli.format.iter().map(|f| parse_format(f)).collect::<Result<_, _>>()?;
    }
    let mut wanted: Vec<Input> = params.formats.iter().flat_map(|f| needs(*f).iter().copied()).collect();
    wanted.sort();
    wanted.dedup();
    let format_needing =
        |input: Input| params.formats.iter().find(|f| needs(**f).contains(&input)).map_or("", |f| f.name());
    let read = |input: Input| -> Result<bool, StageError> {
        let present = wanted.contains(&input);
        if present && !cli.dir.join(input.file_name()).exists() {
            return Err(StageError::input(format!(
                "format `{}` needs {}, which {} lacks: run the stages that write it first (`cargo xtask run`)",
                format_needing(input),
                input.file_name(),
                cli.dir.display()
            )));
        }
        Ok(present)
    };
    let skeleton = read(Input::Skeleton)?.then(|| load(&cli.dir, Input::Skeleton)).transpose()?;
    let hydro = read(Input::Hydro)?.then(|| load(&cli.dir, Input::Hydro)).transpose()?;
    let mesh = read(Input::Mesh)?.then(|| load(&cli.dir, Input::Mesh)).transpose()?;
    let metrics = read(Input::Metrics)?.then(|| load(&cli.dir, Input::Metrics)).transpose()?;
    let samples = read(Input::Samples)?.then(|| load(&cli.dir, Input::Samples)).transpose()?;
    let inputs = Inputs {
        skeleton: skeleton.as_ref(),
        hydro: hydro.as_ref(),
        mesh: mesh.as_ref(),
        metrics: metrics.as_ref(),
        samples: samples.as_ref(),
        scene: scene.as_ref(),
    };
    let manifest = export(&inputs, &params, &cli.dir).map_err(StageError::input)?;
    if cli.json {
        let text = serde_json::to_string_pretty(&manifest).map_err(|e| StageError::failure(e.to_string()))?;
        println!("{text}");
    } else {
        for f in &manifest.files {
            println!(
                "{:<14} {:>12} bytes  {}",
                f.format,
                f.bytes,
                cli.dir.join(karst_export::FOLDER).join(&f.name).display()
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

fn load<P: Payload>(dir: &Path, input: Input) -> Result<P, StageError> {
    Ok(read_artifact::<P>(&dir.join(input.file_name()))?.1)
}
