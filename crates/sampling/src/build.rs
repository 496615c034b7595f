//! The sampling algorithm's entry: key points, then the surfaces, then the volume.

use glam::DVec3;

use karst_geology::Surface;
use karst_scene::rng::Random;
use karst_stage::progress;

use crate::error::SamplingError;
use crate::order::morton_permutation;
use crate::payload::{Samples, Tag};
use crate::poisson::Sampler;
use crate::spacing::SpacingField;
use crate::surfaces::fill_surface;
use crate::view::SamplingView;

/// Surfaces of one kind, the tag of their samples and their random stream's name.
type SurfaceList<'a> = (&'a [Surface], fn(u32) -> Tag, &'static str);

/// Samples the bedrock of the scene: key points first, then samples on the water tables,
/// horizons and faults, then the volume, all outside no-karst volumes and below the terrain.
pub fn build(view: &SamplingView) -> Result<Samples, SamplingError> {
    crate::estimate::check(view)?;
    let field = SpacingField::of_view(view);
    let d = view.domain;
    // Background cells of the volume's base radius (a few samples each, linked lists).
    let base = view.sampling.radius_metres(view.domain, view.terrain);
    let cell = field.min().max(base);
    let mut sampler = Sampler::new(&field, d.min(), d.max(), cell);
    // Runs of equal tags (the tags themselves are built once the grid is freed).
    let mut runs: Vec<(Tag, usize)> = Vec::new();
    for (i, k) in view.keypoints.iter().enumerate() {
        sampler.force(k.point());
        runs.push((Tag::KeyPoint(i as u32), 1));
    }
    let region =
        |p: DVec3| d.contains(p) && p.z < view.terrain.height(p.x, p.y) && !view.geology.in_no_karst(p);
    let attempts = view.sampling.attempts;
    // Surface patches of r/√3, so that one sample covers its patch.
    let frame = (d.min(), d.max(), cell / 3f64.sqrt());
    let g = view.geology;
    let lists: [SurfaceList; 3] = [
        (&g.water_tables, Tag::WaterTable, "water tables"),
        (&g.horizons, Tag::Horizon, "horizons"),
        (&g.faults, Tag::Fault, "faults"),
    ];
    for (surfaces, tag, purpose) in lists {
        for (i, s) in surfaces.iter().enumerate() {
            let key = Random::stream(view.seed, "sampling", &format!("{purpose} {i}")).uniform().to_bits();
            let before = sampler.count();
            fill_surface(&mut sampler, s, frame, attempts, key, region);
            runs.push((tag(i as u32), sampler.count() - before));
        }
    }
    let key = Random::stream(view.seed, "sampling", "volume").uniform().to_bits();
    let bar = progress::bar(sampler.work() as u64, "sampling");
    sampler.fill_volume(key, region, |n| bar.set_position(n));
    bar.finish_and_clear();
    let volume = sampler.count() - runs.iter().map(|r| r.1).sum::<usize>();
    runs.push((Tag::Volume, volume));
    if sampler.count() == view.keypoints.len() {
        return Err(SamplingError::NothingToSample {
            smallest: field.min(),
            radius: view.sampling.radius_in_units(view.domain, view.terrain),
        });
    }
    // Free the background grid first: the positions are copied out of its records (32 bytes a
    // sample, so not in place), then converted in place.
    let positions: Vec<[f64; 3]> = sampler.into_points().into_iter().map(|p| p.to_array()).collect();
    let mut tags = Vec::with_capacity(sampler_len(&runs));
    for (tag, n) in runs {
        tags.resize(tags.len() + n, tag);
    }
    // Stored along a space-filling curve, so that the later stages' walks from a sample to
    // its neighbours stay in cache (see `order.rs`).
    let order =
        morton_permutation(&positions, view.keypoints.len(), (d.min().to_array(), d.max().to_array()));
    let (positions, tags) = (permuted(positions, &order), permuted(tags, &order));
    Ok(Samples { positions, tags, radius: field.min(), radius_field: field })
}

/// `values` in the order `order` (a permutation of its indices).
fn permuted<T: Copy>(values: Vec<T>, order: &[u32]) -> Vec<T> {
    order.iter().map(|&i| values[i as usize]).collect()
}

fn sampler_len(runs: &[(Tag, usize)]) -> usize {
    runs.iter().map(|r| r.1).sum()
}
