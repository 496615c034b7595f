//! The binary's commands. The lead registers the stage in the pipeline (artifact kind, key,
//! runner); until then `streams.json` is written as plain pretty JSON, atomically.

use std::path::{Path, PathBuf};
use std::time::Instant;

use karst_artifact::cli::RunArgs;
use karst_artifact::{StageError, read_artifact};
use karst_geology::Scene;
use karst_hydro::Hydro;

use crate::{Streams, build};

/// `karst-streams run`: the headline.
pub fn run(args: &RunArgs) -> Result<String, StageError> {
    let scene = Scene::load(&args.scene)?;
    let hydro_path = args.out.join("hydro.json");
    let (_, hydro) = read_artifact::<Hydro>(&hydro_path)?;
    let start = Instant::now();
    let streams = build(&scene, &hydro).map_err(|e| {
        let file = if e.concerns_scene() { args.scene.clone() } else { hydro_path.clone() };
        StageError::input(format!("{}: {e}", file.display()))
    })?;
    let seconds = start.elapsed().as_secs_f64();
    let path = args.out.join("streams.json");
    write(&path, &streams)?;
    for r in &streams.reports {
        eprintln!("note: {r}");
    }
    Ok(format!("{} in {seconds:.3} s", streams.headline()))
}

/// Writes `streams` as pretty JSON, atomically.
pub fn write(path: &Path, streams: &Streams) -> Result<(), StageError> {
    let mut bytes = serde_json::to_vec_pretty(streams)
        .map_err(|e| StageError::failure(format!("cannot encode {}: {e}", path.display())))?;
    bytes.push(b'\n');
    karst_artifact::atomic::write_bytes(path, &bytes)
        .map_err(|e| StageError::failure(format!("cannot write {}: {e}", path.display())))
}

/// Reads a streams.json.
pub fn read(path: &Path) -> Result<Streams, StageError> {
    let text = std::fs::read(path)
        .map_err(|e| StageError::input(format!("{}: cannot read: {e}", path.display())))?;
    serde_json::from_slice(&text)
        .map_err(|e| StageError::input(format!("{}: not a streams.json: {e}", path.display())))
}

/// `karst-streams render SCENE DIR [--png FILE]`.
#[derive(Debug, Clone, clap::Args)]
pub struct RenderArgs {
    /// The scene file (for its terrain).
    pub scene: PathBuf,
    /// Folder holding streams.json.
    pub dir: PathBuf,
    /// The picture to write; default DIR/streams.png.
    #[arg(long)]
    pub png: Option<PathBuf>,
}

pub fn render(args: &RenderArgs) -> Result<(), StageError> {
    let scene = Scene::load(&args.scene)?;
    let streams = read(&args.dir.join("streams.json"))?;
    let png = args.png.clone().unwrap_or_else(|| args.dir.join("streams.png"));
    crate::render::map(&scene, &streams)
        .write_png(&png)
        .map_err(|e| StageError::failure(format!("cannot write {}: {e}", png.display())))?;
    println!("{}", png.display());
    Ok(())
}

/// `karst-streams inspect FILE`.
#[derive(Debug, Clone, clap::Args)]
pub struct InspectArgs {
    pub file: PathBuf,
}

pub fn inspect(args: &InspectArgs) -> Result<(), StageError> {
    let s = read(&args.file)?;
    println!("{}: {}", args.file.display(), s.headline());
    for (w, metres) in s.lengths() {
        println!("  {:<9} {metres:8.1} m", w.name());
    }
    for p in &s.pools {
        println!("  pool      {:?} at z {:.2}, {:.0} m², {:.2} m deep", p.kind, p.level, p.area, p.depth);
    }
    for r in &s.reports {
        println!("  report    {r}");
    }
    Ok(())
}
