//! The cell the cave and the water are meshed at, chosen from the sizes of the karst's passages,
//! and the floor on the conduits' half-thickness that keeps the thinner ones open at that cell
//! ([`thickened`]); read by the mesher's build and by its work estimate before any cell is
//! evaluated.

use karst_sdf::{SdfModel, SectionSpec};

use crate::spheres::Spheres;

/// The cell of the cave alone and the water: `requested` when positive, else the
/// [`CAVE_PERCENTILE`] of the passages' sizes ([`passage_sizes`]: the half-thickness along
/// each passage, as its profile samples it) weighted by the length of passage each stands for,
/// at most `cell_size` and at least `cell_size` / [`CAVE_REFINE`]. The leaves thinner than the cell, a passage's pinches among them, are
/// meshed at the cell's half-thickness ([`thickened`]), so that every conduit is at least a
/// cell thick: every point of space is within √3/2 cells of a lattice point, so such a conduit
/// always holds lattice points and cannot fall between them. A pinch is therefore drawn one
/// cell thick, never closed, and the cell does not follow it: with passage profiles (`[sdf]
/// passage_detail`) a passage pinches to crawls every few tens of metres, and a cell that
/// followed every pinch would cost the inverse square of its size over the whole cave.
pub fn cave_cell(model: &SdfModel, cell_size: f64, requested: f64) -> f64 {
    cave_cells(model, requested)(cell_size)
}

/// [`cave_cell`] at any terrain cell, the passages' sizes read once (the work estimate tries
/// several cells).
pub fn cave_cells(model: &SdfModel, requested: f64) -> impl Fn(f64) -> f64 {
    let automatic = requested <= 0.0;
    let size = automatic.then(|| weighted_percentile(&mut passage_sizes(model), CAVE_PERCENTILE)).flatten();
    move |cell_size| {
        if automatic {
            size.unwrap_or(cell_size).clamp(cell_size / CAVE_REFINE, cell_size)
        } else {
            requested
        }
    }
}

/// The automatic cave cell is at most this many times finer than the terrain's (the cost grows
/// as its square).
pub const CAVE_REFINE: f64 = 8.0;

/// The share of the passages' length (0..1) thinner than the automatic cave cell: the cell
/// follows the common passages, not the thinnest, whose cost would grow as the inverse square
/// of their size over the whole cave.
pub const CAVE_PERCENTILE: f64 = 0.5;

/// Each passage's half-thickness, metres, with its length: each sweep (a segment, or a piece
/// of a segment's passage profile) the mean of its end sections' depths at the axis
/// ([`section_depth`]); a tortuous conduit's group of spheres the mean
/// radius of the spheres of its axis ([`Spheres::axis`], the largest sphere of each station,
/// each standing for its diameter; the smaller ones filling the sections out to their corners
/// are not passages of their own); a capsule its radius along its axis, a chamber its radius
/// over its diameter.
pub fn passage_sizes(model: &SdfModel) -> Vec<(f64, f64)> {
    let length = |a: [f64; 3], b: [f64; 3]| (0..3).map(|i| (a[i] - b[i]).powi(2)).sum::<f64>().sqrt();
    let f = |p: [f32; 3]| p.map(f64::from);
    let mut sizes = Vec::new();
    sizes.extend(model.capsules.iter().map(|c| (c.radius, length(c.a, c.b).max(2.0 * c.radius))));
    // A run of sweeps through a passage profile: each piece, as the profile samples the
    // passage. A segment without a profile is one piece.
    sizes.extend(model.sweeps.iter().map(|s| {
        let piece = length(f(s.sweep.a), f(s.sweep.b));
        (((section_depth(&s.sweep.start) + section_depth(&s.sweep.end)) / 2.0), piece)
    }));
    for group in &model.spheres {
        let spheres = Spheres::of(&group.spheres);
        let (sum, along) = spheres
            .axis()
            .map(|s| s[3] as f64)
            .fold((0.0, 0.0), |(sum, along), r| (sum + 2.0 * r * r, along + 2.0 * r));
        if along > 0.0 {
            sizes.push((sum / along, along));
        }
    }
    sizes.extend(model.chambers.iter().map(|c| (c.radius as f64, 2.0 * c.radius as f64)));
    sizes.retain(|&(r, w)| r > 0.0 && r.is_finite() && w.is_finite());
    sizes
}

/// Each karst leaf's half-thickness, metres (capsule or sphere radius, half the smaller side
/// of each section of a sweep, chamber radius): what [`thickened`] raises to the cell.
fn half_thicknesses(model: &SdfModel) -> impl Iterator<Item = f64> + '_ {
    let capsules = model.capsules.iter().map(|c| c.radius);
    let sweeps = model.sweeps.iter().flat_map(|s| [&s.sweep.start, &s.sweep.end].map(section_half_thickness));
    let spheres = model.spheres.iter().flat_map(|g| g.spheres.iter().map(|s| s[3] as f64));
    let chambers = model.chambers.iter().map(|c| c.radius as f64);
    capsules.chain(sweeps).chain(spheres).chain(chambers)
}

/// A section's half-thickness where a caver stands: its depth at the axis (the radius of the
/// sphere inscribed there, as a tortuous conduit's stations take it), or half its smaller side
/// when the axis lies outside it. A canyon's or a keyhole's slot is narrower than its
/// half-width times its height factor, which half the smaller side would count.
fn section_depth(s: &SectionSpec) -> f64 {
    let depth = -s.section().distance(glam::DVec2::ZERO);
    if depth > 0.0 { depth } else { section_half_thickness(s) }
}

/// Half the smaller side of a section.
fn section_half_thickness(s: &SectionSpec) -> f64 {
    (s.shape.radius * s.shape.ratio.min(1.0)) as f64
}

/// The smallest value v of `(value, weight)` pairs such that the values ≤ v weigh at least
/// `share` of the total (None when there are none or they weigh nothing).
pub fn weighted_percentile(pairs: &mut [(f64, f64)], share: f64) -> Option<f64> {
    pairs.sort_by(|a, b| a.0.total_cmp(&b.0));
    let total: f64 = pairs.iter().map(|p| p.1).sum();
    if pairs.is_empty() || total <= 0.0 {
        return pairs.first().map(|p| p.0);
    }
    let mut below = 0.0;
    for &(value, weight) in pairs.iter() {
        below += weight;
        if below >= share * total {
            return Some(value);
        }
    }
    pairs.last().map(|p| p.0)
}

/// `model` with every karst leaf at least `floor` thick on each side: capsule, sphere and
/// chamber radii raised to `floor`, each section's half-width and half-height raised to
/// `floor` (the other kept, its asymmetry kept). The mesher meshes this model, so that a
/// conduit thinner than the cave cell is drawn one cell thick (its true size stays in sdf.bin
/// and in the survey); the model is unchanged when no leaf is thinner.
pub fn thickened(model: &SdfModel, floor: f64) -> Option<SdfModel> {
    let thin = half_thicknesses(model).any(|r| r < floor);
    if !thin {
        return None;
    }
    let floor32 = floor as f32;
    let mut out = model.clone();
    for c in &mut out.capsules {
        c.radius = c.radius.max(floor);
    }
    for s in &mut out.sweeps {
        for section in [&mut s.sweep.start, &mut s.sweep.end] {
            let shape = &mut section.shape;
            let height = (shape.radius * shape.ratio).max(floor32);
            shape.radius = shape.radius.max(floor32);
            shape.ratio = height / shape.radius;
        }
    }
    for group in &mut out.spheres {
        for s in &mut group.spheres {
            s[3] = s[3].max(floor32);
        }
    }
    for c in &mut out.chambers {
        c.radius = c.radius.max(floor32);
    }
    Some(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_weighted_percentile_counts_the_length_each_value_stands_for() {
        let mut pairs = vec![(3.0, 10.0), (0.5, 1.0), (1.0, 9.0)];
        assert_eq!(weighted_percentile(&mut pairs, 0.05), Some(0.5));
        assert_eq!(weighted_percentile(&mut pairs, 0.1), Some(1.0));
        assert_eq!(weighted_percentile(&mut pairs, 0.5), Some(1.0));
        assert_eq!(weighted_percentile(&mut pairs, 0.51), Some(3.0));
        assert_eq!(weighted_percentile(&mut [], 0.1), None);
    }
}
