//! The sampling stage: scene in, `samples.bin` out.

use std::time::Instant;

use glam::DVec3;

use karst_artifact::cli::{InspectArgs, RunArgs, StageRun, print_json};
use karst_artifact::{Stage, StageError, read_artifact, write_artifact};
use karst_geology::Scene;
use karst_geology::rng::Random;

use karst_artifact::progress;
use karst_geology::Surface;

use crate::poisson::Sampler;
use crate::radius::RadiusField;
use crate::surfaces::fill_surface;
use crate::{Samples, Tag};

/// Surfaces of one kind, the tag of their samples and their random stream's name.
type SurfaceList<'a> = (&'a [Surface], fn(u32) -> Tag, &'static str);

/// Samples the bedrock of `scene`: key points first, then samples on the water tables,
/// horizons and faults, then the volume, all outside no-karst volumes and below the terrain.
pub fn sample_scene(scene: &Scene) -> Result<Samples, StageError> {
    let field = RadiusField::of_scene(scene);
    let d = &scene.domain;
    // Background cells of the volume's base radius (a few samples each, linked lists).
    let base = scene.sampling.radius * crate::radius::unit_scale(scene);
    let cell = field.min().max(base);
    let mut sampler = Sampler::new(&field, d.min(), d.max(), cell);
    // Runs of equal tags (the tags themselves are built once the grid is freed).
    let mut runs: Vec<(Tag, usize)> = Vec::new();
    for (i, k) in scene.keypoints.iter().enumerate() {
        sampler.force(k.point());
        runs.push((Tag::KeyPoint(i as u32), 1));
    }
    let region =
        |p: DVec3| d.contains(p) && p.z < scene.terrain.height(p.x, p.y) && !scene.geology.in_no_karst(p);
    let attempts = scene.sampling.attempts;
    // Surface patches of r/√3, so that one sample covers its patch.
    let frame = (d.min(), d.max(), cell / 3f64.sqrt());
    let g = &scene.geology;
    let lists: [SurfaceList; 3] = [
        (&g.water_tables, Tag::WaterTable, "water tables"),
        (&g.horizons, Tag::Horizon, "horizons"),
        (&g.faults, Tag::Fault, "faults"),
    ];
    for (surfaces, tag, purpose) in lists {
        for (i, s) in surfaces.iter().enumerate() {
            let key = Random::stream(scene.seed, "sampling", &format!("{purpose} {i}")).uniform().to_bits();
            let before = sampler.points.len();
            fill_surface(&mut sampler, s, frame, attempts, key, region);
            runs.push((tag(i as u32), sampler.points.len() - before));
        }
    }
    let key = Random::stream(scene.seed, "sampling", "volume").uniform().to_bits();
    let bar = progress::bar(sampler.work() as u64, "sampling");
    sampler.fill_volume(key, region, |n| bar.set_position(n));
    bar.finish_and_clear();
    let volume = sampler.points.len() - runs.iter().map(|r| r.1).sum::<usize>();
    runs.push((Tag::Volume, volume));
    if sampler.points.len() == scene.keypoints.len() {
        return Err(StageError::input(format!(
            "sampling.radius: no sample fits in the bedrock: the domain below the terrain and outside the no-karst volumes is empty or thinner than the radius ({} m at the smallest, sampling.radius = {})",
            field.min(),
            scene.sampling.radius
        )));
    }
    // Free the background grid first, and convert the positions in place: peak memory stays
    // near the samples themselves.
    let points = std::mem::take(&mut sampler.points);
    drop(sampler);
    let positions = points.into_iter().map(|p| p.to_array()).collect();
    let mut tags = Vec::with_capacity(sampler_len(&runs));
    for (tag, n) in runs {
        tags.resize(tags.len() + n, tag);
    }
    Ok(Samples { positions, tags, radius: field.min(), radius_field: field })
}

fn sampler_len(runs: &[(Tag, usize)]) -> usize {
    runs.iter().map(|r| r.1).sum()
}

/// `karst-sampling run`.
pub fn run(args: &RunArgs) -> Result<String, StageError> {
    let scene = Scene::load(&args.scene)?;
    let run = StageRun::new(Stage::Sampling, &args.out);
    let start = Instant::now();
    let samples =
        sample_scene(&scene).map_err(|e| StageError::input(format!("{}: {e}", args.scene.display())))?;
    write_artifact(&run.output_path(), &run.provenance(&scene.params_hash(Stage::Sampling)), &samples)?;
    let c = samples.tag_counts();
    Ok(format!(
        "{} samples ({} key points, {} on water tables, {} on horizons, {} on faults) in {:.2} s",
        samples.len(),
        c.keypoint,
        c.water_table,
        c.horizon,
        c.fault,
        start.elapsed().as_secs_f64()
    ))
}

/// `karst-sampling inspect`.
pub fn inspect(args: &InspectArgs) -> Result<(), StageError> {
    if args.json {
        return print_json::<Samples>(&args.file);
    }
    let (header, samples) = read_artifact::<Samples>(&args.file)?;
    let c = samples.tag_counts();
    println!("{}: samples, schema {}, by {}", args.file.display(), header.schema, header.producer);
    println!("  samples     {}", samples.len());
    println!("  volume      {}", c.volume);
    println!("  key points  {}", c.keypoint);
    println!("  water table {}", c.water_table);
    println!("  horizons    {}", c.horizon);
    println!("  faults      {}", c.fault);
    let f = &samples.radius_field;
    println!(
        "  radius      {} m at the smallest, field of {:?} nodes every {} m",
        samples.radius, f.size, f.cell
    );
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
