//! Sampling on the surfaces themselves (Paris et al. 2021 §4.1: samples on the inception
//! horizons let paths run exactly along them; KarstNSim §1.1 does the same on water tables).
//!
//! A surface is cut into patches that map the unit square onto it: a plane into squares of
//! edge h (the patch size the stage gives) in its own (strike, dip) frame, centred on the point
//! of the plane nearest the domain's centre and covering the domain's diagonal (patches that
//! miss the domain are dropped); a TIN into ⌈area/h²⌉ slots per triangle, mapped uniformly onto
//! it. Patches are computed from their index, not stored. Every patch gets one dart per pass
//! and retires after `attempts` consecutive failures, when the disk of the sample that rejects
//! a dart covers it entirely, or, for squares whose diagonal is below the smallest radius,
//! once it holds its one sample. A dart lies on the surface (up to rounding), so surface
//! samples are exactly on their horizon or water table.

use glam::DVec3;
use rayon::prelude::*;

use karst_geology::{Geometry, Surface};

use crate::poisson::{CellRng, Sampler};

/// A map from [0, 1)² onto part of a surface.
enum Patch {
    Square { corner: DVec3, u: DVec3, v: DVec3 },
    Triangle { a: DVec3, b: DVec3, c: DVec3 },
}

impl Patch {
    /// True when the patch lies inside the disk of radius `r` around `q`.
    fn inside(&self, q: DVec3, r: f64) -> bool {
        let r2 = r * r;
        match self {
            Patch::Square { corner, u, v } => [*corner, *corner + *u, *corner + *v, *corner + *u + *v]
                .iter()
                .all(|c| c.distance_squared(q) < r2),
            Patch::Triangle { a, b, c } => [a, b, c].iter().all(|c| c.distance_squared(q) < r2),
        }
    }

    fn point(&self, s: f64, t: f64) -> DVec3 {
        match self {
            Patch::Square { corner, u, v } => *corner + *u * s + *v * t,
            Patch::Triangle { a, b, c } => {
                // Uniform on the triangle (Osada et al. 2002).
                let r = s.sqrt();
                *a * (1.0 - r) + *b * (r * (1.0 - t)) + *c * (r * t)
            }
        }
    }
}

impl Patch {
    /// The patch's bounding box.
    fn bounds(&self) -> (DVec3, DVec3) {
        let corners = match self {
            Patch::Square { corner, u, v } => [*corner, *corner + *u, *corner + *v, *corner + *u + *v],
            Patch::Triangle { a, b, c } => [*a, *b, *c, *c],
        };
        corners.iter().fold((corners[0], corners[0]), |(l, h), p| (l.min(*p), h.max(*p)))
    }
}

/// The patches of a surface, each computed from its index when needed (no list is kept: a
/// plane over a large domain has hundreds of thousands of them).
enum Patches {
    /// `count` × `count` squares of `u`, `v` around `origin`.
    Plane { origin: DVec3, u: DVec3, v: DVec3, count: usize },
    /// Triangle `slots[i]` of the mesh, ⌈area/h²⌉ slots per triangle.
    Tin { triangles: Vec<[DVec3; 3]>, slots: Vec<u32> },
}

impl Patches {
    fn new(surface: &Surface, centre: DVec3, half_diagonal: f64, cell: f64) -> Patches {
        match &surface.geometry {
            Geometry::Plane { .. } => {
                let n = surface.normal();
                let strike = if n.truncate().length() < 1e-12 {
                    DVec3::X
                } else {
                    DVec3::new(-n.y, n.x, 0.0).normalize()
                };
                let dip = n.cross(strike);
                let count = (2.0 * half_diagonal / cell).ceil() as usize;
                Patches::Plane {
                    origin: surface.closest_point(centre),
                    u: strike * cell,
                    v: dip * cell,
                    count,
                }
            }
            Geometry::Tin { mesh, .. } => {
                let triangles: Vec<[DVec3; 3]> =
                    (0..mesh.triangles.len()).map(|t| mesh.triangle(t)).collect();
                let mut slots = Vec::new();
                for (t, [a, b, c]) in triangles.iter().enumerate() {
                    let n =
                        (0.5 * (*b - *a).cross(*c - *a).length() / (cell * cell)).ceil().max(1.0) as usize;
                    slots.extend(std::iter::repeat_n(t as u32, n));
                }
                Patches::Tin { triangles, slots }
            }
        }
    }

    fn len(&self) -> usize {
        match self {
            Patches::Plane { count, .. } => count * count,
            Patches::Tin { slots, .. } => slots.len(),
        }
    }

    fn get(&self, i: usize) -> Patch {
        match self {
            Patches::Plane { origin, u, v, count } => {
                let (x, y) =
                    ((i % count) as f64 - (count / 2) as f64, (i / count) as f64 - (count / 2) as f64);
                Patch::Square { corner: *origin + *u * x + *v * y, u: *u, v: *v }
            }
            Patches::Tin { triangles, slots } => {
                let [a, b, c] = triangles[slots[i] as usize];
                Patch::Triangle { a, b, c }
            }
        }
    }
}

/// Adds samples on `surface` inside `region` ⊂ the box lo–hi; `cell` is the patch size, `key`
/// seeds the random streams.
///
/// Phase groups, as for the volume: the patches are binned by the lower corner of their
/// bounding box in bins of edge (largest patch extent + largest radius), and the bins coloured
/// by the parity of their coordinates. Two patches of bins of one colour are then more than the
/// largest radius apart and never conflict: the bins of a colour are filled in parallel, each
/// from its own random stream against the samples already in the grid plus its own, and their
/// samples are inserted in bin order after each colour, so the result does not depend on the
/// number of threads.
pub fn fill_surface(
    sampler: &mut Sampler,
    surface: &Surface,
    (lo, hi, cell): (DVec3, DVec3, f64),
    attempts: u32,
    key: u64,
    region: impl Fn(DVec3) -> bool + Sync,
) {
    let (centre, half_diagonal) = ((lo + hi) * 0.5, 0.5 * (hi - lo).length());
    let patches = Patches::new(surface, centre, half_diagonal, cell);
    // The bounding boxes of the patches that may meet the domain: their largest extent and
    // the lowest corner (a first pass, so that no list of corners is kept).
    let meets = |i: usize| {
        let (l, h) = patches.get(i).bounds();
        (l.cmple(hi).all() && h.cmpge(lo).all()).then_some((l, h))
    };
    let (extent, origin) = (0..patches.len())
        .into_par_iter()
        .filter_map(meets)
        .map(|(l, h)| ((h - l).max_element(), l))
        .reduce(|| (0.0, DVec3::INFINITY), |a, b| (a.0.max(b.0), a.1.min(b.1)));
    if extent == 0.0 && origin == DVec3::INFINITY {
        return;
    }
    let bin = (extent + sampler.max_radius()) * (1.0 + 1e-9) + 1e-9;
    let coords = |l: DVec3| ((l - origin) / bin).floor().as_uvec3();
    let dims = (((hi - origin) / bin).floor().max(DVec3::ZERO).as_uvec3() + 1).as_u64vec3();
    // (colour << 61 | bin index, patch), sorted: colours in order, bins in order in a colour.
    let mut order: Vec<(u64, u32)> = (0..patches.len())
        .into_par_iter()
        .filter_map(|i| {
            let c = coords(meets(i)?.0).min((dims - 1).as_uvec3());
            let colour = ((c.x & 1) | (c.y & 1) << 1 | (c.z & 1) << 2) as u64;
            let c = c.as_u64vec3();
            Some((colour << 61 | (c.x + dims.x * (c.y + dims.y * c.z)), i as u32))
        })
        .collect();
    order.par_sort_unstable();
    let attempts = attempts.min(255) as u8;
    // A square patch whose diagonal is below the smallest radius holds one sample at most.
    let single = matches!(patches, Patches::Plane { .. }) && cell * 2f64.sqrt() < sampler.min_radius();
    let mut start = 0;
    while start < order.len() {
        let colour = order[start].0 >> 61;
        let end = start + order[start..].partition_point(|o| o.0 >> 61 == colour);
        // The bins of this colour: ranges of `order`.
        let mut bins = Vec::new();
        let mut b = start;
        while b < end {
            let e = b + order[b..end].partition_point(|o| o.0 == order[b].0);
            bins.push(b..e);
            b = e;
        }
        let this = &*sampler;
        let found: Vec<Vec<(DVec3, f32)>> = bins
            .par_iter()
            .map(|range| {
                let group = &order[range.clone()];
                let mut rng = CellRng::new(key, 0, group[0].0 as usize);
                fill_bin(this, &patches, group, attempts, single, &mut rng, &region)
            })
            .collect();
        sampler.extend(found.into_iter().flatten());
        start = end;
    }
}

/// Throws darts on the patches of one bin until each retires (see the module's
/// documentation); returns the new samples.
fn fill_bin(
    sampler: &Sampler,
    patches: &Patches,
    group: &[(u64, u32)],
    attempts: u8,
    single: bool,
    rng: &mut CellRng,
    region: &impl Fn(DVec3) -> bool,
) -> Vec<(DVec3, f32)> {
    let list: Vec<Patch> = group.iter().map(|o| patches.get(o.1 as usize)).collect();
    let (mut l, mut h) = list[0].bounds();
    for p in &list[1..] {
        let (a, b) = p.bounds();
        (l, h) = (l.min(a), h.max(b));
    }
    let mut near = Vec::new();
    sampler.gather(l, h, &mut near);
    let mut out = Vec::new();
    let mut misses = vec![0u8; list.len()];
    let mut live: Vec<u32> = (0..list.len() as u32).collect();
    let r_min = sampler.min_radius();
    while !live.is_empty() {
        live.retain(|&i| {
            let i = i as usize;
            let patch = &list[i];
            let p = patch.point(rng.uniform(), rng.uniform());
            if !region(p) {
                misses[i] += 1;
                return misses[i] < attempts;
            }
            let r = sampler.radius_at(p);
            let blocker = near.iter().find(|(q, rq)| {
                let m = r.min(*rq);
                q.distance_squared(p) < m * m
            });
            match blocker {
                None => {
                    near.push((p, r));
                    out.push((p, r as f32));
                    if single {
                        return false;
                    }
                    misses[i] = 0;
                }
                // A disk that covers the whole patch (its corners) leaves it nothing.
                Some(&(q, rq)) if patch.inside(q, rq.min(r_min)) => return false,
                Some(_) => misses[i] += 1,
            }
            misses[i] < attempts
        });
    }
    out
}
