//! The hydro stage: `skeleton.json` in; `hydro.json`, `hydro_nodes.csv` and `hydro_links.csv`
//! out; `render` draws the water types.

use std::path::PathBuf;
use std::time::Instant;

use karst_artifact::cli::{InspectArgs, RunArgs, StageRun, print_json};
use karst_artifact::{Stage, StageError, read_artifact, write_artifact};
use karst_geology::params::Recharge;
use karst_geology::{KeyPointKind, Scene};
use karst_skeleton::Skeleton;

use crate::water::WaterType;
use crate::{Hydro, Inputs, compute, export, recharge, render};

/// `karst-hydro run`.
pub fn run(args: &RunArgs) -> Result<String, StageError> {
    let scene = Scene::load(&args.scene)?;
    let mut run = StageRun::new(Stage::Hydro, &args.out);
    let skeleton: Skeleton = run.read_input(Stage::Skeleton)?;
    let start = Instant::now();
    let inputs = Inputs {
        spring_names: scene.keypoints_of(KeyPointKind::Spring).map(|(_, k)| k.name.clone()).collect(),
        recharge: match scene.hydro.recharge {
            Recharge::Weight => Vec::new(),
            Recharge::Catchment => recharge::catchments(&scene)
                .into_iter()
                .zip(scene.keypoints_of(KeyPointKind::Sink))
                .map(|((name, area), (_, k))| (name, area * k.weight))
                .collect(),
        },
    };
    let hydro = compute(&skeleton, &scene.hydro, &inputs).map_err(|e| {
        let file = if e.concerns_scene() { args.scene.clone() } else { run.path_of(Stage::Skeleton) };
        StageError::input(format!("{}: {e}", file.display()))
    })?;
    write_artifact(&run.output_path(), &run.provenance(&scene.params_hash(Stage::Hydro)), &hydro)?;
    export::write(&args.out, &skeleton, &hydro).map_err(|e| {
        StageError::failure(format!("cannot write the CSV tables in {}: {e}", args.out.display()))
    })?;
    let total: f64 = hydro.springs.iter().map(|s| s.flow).sum();
    let dry = hydro.conduits.iter().filter(|c| c.dry).count();
    let segments = || hydro.conduits.iter().flat_map(|c| &c.segments);
    let falls = segments().filter(|s| s.water.is_free_fall()).count();
    let sumps = segments().filter(|s| s.water == WaterType::Sump).count();
    Ok(format!(
        "{} conduits ({dry} dry), {falls} free-fall and {sumps} sump segments, recharge {total} to {} spring(s) in {:.2} s",
        hydro.conduits.len(),
        hydro.springs.len(),
        start.elapsed().as_secs_f64()
    ))
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
    let (_, skeleton) = read_artifact::<Skeleton>(&args.dir.join(Stage::Skeleton.file_name()))?;
    let (_, hydro) = read_artifact::<Hydro>(&args.dir.join(Stage::Hydro.file_name()))?;
    if hydro.conduits.len() != skeleton.conduits.len() {
        return Err(StageError::input(format!(
            "hydro.json describes {} conduits, skeleton.json has {}: rerun `cargo xtask run --from hydro`",
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

/// `karst-hydro inspect`.
pub fn inspect(args: &InspectArgs) -> Result<(), StageError> {
    if args.json {
        return print_json::<Hydro>(&args.file);
    }
    let (header, hydro) = read_artifact::<Hydro>(&args.file)?;
    let max = hydro.conduits.iter().map(|c| c.flow).fold(0.0, f64::max);
    println!("{}: hydro, schema {}, by {}", args.file.display(), header.schema, header.producer);
    println!(
        "  conduits  {} ({} dry), largest flow {max}",
        hydro.conduits.len(),
        hydro.conduits.iter().filter(|c| c.dry).count()
    );
    for w in WaterType::ALL {
        let n = hydro.conduits.iter().flat_map(|c| &c.segments).filter(|s| s.water == w).count();
        if n > 0 {
            println!("  {:<9} {n} segment(s)", w.name());
        }
    }
    for s in &hydro.sinks {
        println!("  sink      {}: {}", s.name, s.recharge);
    }
    for s in &hydro.springs {
        println!("  spring    {}: {}", s.name, s.flow);
    }
    Ok(())
}
