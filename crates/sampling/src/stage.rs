//! The sampling stage: scene in, `samples.bin` out.

use std::time::Instant;

use glam::DVec3;

use karst_artifact::cli::{InspectArgs, RunArgs, StageRun, print_json};
use karst_artifact::{Stage, StageError, read_artifact, write_artifact};
use karst_geology::Scene;
use karst_geology::rng::Random;

use crate::{Samples, Tag, poisson};

/// Samples the bedrock of `scene`: key points first, then Poisson-disk samples below the
/// terrain.
pub fn sample_scene(scene: &Scene) -> Result<Samples, StageError> {
    let fixed: Vec<DVec3> = scene.keypoints.iter().map(|k| k.point()).collect();
    let mut rng = Random::stream(scene.seed, "sampling", "poisson");
    let terrain = &scene.terrain;
    let below_ground = |p: DVec3| p.z < terrain.height(p.x, p.y);
    let params = &scene.sampling;
    let d = &scene.domain;
    let points =
        poisson::sample(d.min(), d.max(), params.radius, params.attempts, &fixed, below_ground, &mut rng);
    if points.len() == fixed.len() {
        return Err(StageError::input(format!(
            "no sample fits in the bedrock: the domain below the terrain is empty or thinner than sampling.radius = {}",
            params.radius
        )));
    }
    let tags = (0..points.len())
        .map(|i| if i < fixed.len() { Tag::KeyPoint(i as u32) } else { Tag::Volume })
        .collect();
    Ok(Samples { positions: points.iter().map(|p| p.to_array()).collect(), tags, radius: params.radius })
}

/// `karst-sampling run`.
pub fn run(args: &RunArgs) -> Result<String, StageError> {
    let scene = Scene::load(&args.scene)?;
    let run = StageRun::new(Stage::Sampling, &args.out);
    let start = Instant::now();
    let samples = sample_scene(&scene)?;
    write_artifact(&run.output_path(), &run.provenance(&scene.params_hash(Stage::Sampling)), &samples)?;
    let (_, keypoints) = samples.tag_counts();
    Ok(format!(
        "{} samples ({keypoints} key points) in {:.2} s",
        samples.len(),
        start.elapsed().as_secs_f64()
    ))
}

/// `karst-sampling inspect`.
pub fn inspect(args: &InspectArgs) -> Result<(), StageError> {
    if args.json {
        return print_json::<Samples>(&args.file);
    }
    let (header, samples) = read_artifact::<Samples>(&args.file)?;
    let (volume, keypoints) = samples.tag_counts();
    println!("{}: samples, schema {}, by {}", args.file.display(), header.schema, header.producer);
    println!("  samples     {}", samples.len());
    println!("  volume      {volume}");
    println!("  key points  {keypoints}");
    println!("  radius      {} m", samples.radius);
    if let Some((lo, hi)) = bounds(&samples.positions) {
        println!(
            "  bounds      [{:.2}, {:.2}, {:.2}] – [{:.2}, {:.2}, {:.2}]",
            lo[0], lo[1], lo[2], hi[0], hi[1], hi[2]
        );
    }
    println!(
        "  bytes       {} payload ({:.1} per sample)",
        header.payload_len,
        header.payload_len as f64 / samples.len().max(1) as f64
    );
    Ok(())
}

fn bounds(points: &[[f64; 3]]) -> Option<([f64; 3], [f64; 3])> {
    let first = *points.first()?;
    Some(points.iter().fold((first, first), |(mut lo, mut hi), p| {
        for a in 0..3 {
            lo[a] = lo[a].min(p[a]);
            hi[a] = hi[a].max(p[a]);
        }
        (lo, hi)
    }))
}
