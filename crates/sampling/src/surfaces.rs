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

use karst_geology::rng::Random;
use karst_geology::{Geometry, Surface};

use crate::poisson::Sampler;

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

/// True when the patch may meet the box lo–hi (its bounding box overlaps it).
fn meets(patch: &Patch, lo: DVec3, hi: DVec3) -> bool {
    let corners = match patch {
        Patch::Square { corner, u, v } => [*corner, *corner + *u, *corner + *v, *corner + *u + *v],
        Patch::Triangle { a, b, c } => [*a, *b, *c, *c],
    };
    let (l, h) = corners.iter().fold((corners[0], corners[0]), |(l, h), p| (l.min(*p), h.max(*p)));
    l.cmple(hi).all() && h.cmpge(lo).all()
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

/// Adds samples on `surface` inside `region` ⊂ the box lo–hi; `cell` is the patch size.
pub fn fill_surface(
    sampler: &mut Sampler,
    surface: &Surface,
    (lo, hi, cell): (DVec3, DVec3, f64),
    attempts: u32,
    rng: &mut Random,
    region: impl Fn(DVec3) -> bool,
) {
    let (centre, half_diagonal) = ((lo + hi) * 0.5, 0.5 * (hi - lo).length());
    let patches = Patches::new(surface, centre, half_diagonal, cell);
    let mut live: Vec<u32> =
        (0..patches.len() as u32).filter(|i| meets(&patches.get(*i as usize), lo, hi)).collect();
    let mut misses = vec![0u8; patches.len()];
    let attempts = attempts.min(255) as u8;
    // A square patch whose diagonal is below the smallest radius holds one sample at most.
    let single = matches!(patches, Patches::Plane { .. }) && cell * 2f64.sqrt() < sampler.min_radius();
    while !live.is_empty() {
        live.retain(|&i| {
            let i = i as usize;
            let patch = patches.get(i);
            let p = patch.point(rng.uniform(), rng.uniform());
            if !region(p) {
                misses[i] += 1;
                return misses[i] < attempts;
            }
            match sampler.insert_or_blocker(p) {
                Ok(()) if single => return false,
                Ok(()) => misses[i] = 0,
                // A disk that covers the whole patch (its corners) leaves it nothing.
                Err((q, rq)) if patch.inside(q, rq.min(sampler.min_radius())) => return false,
                Err(_) => misses[i] += 1,
            }
            misses[i] < attempts
        });
    }
}
