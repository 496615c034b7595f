//! Poisson-disk sampling in 3D (Bridson 2007) inside an arbitrary region.
//!
//! A background grid of cell r/√3 holds at most one sample per cell, so a candidate only checks
//! the 5×5×5 cells around it. Sampling starts from the fixed points (key points) plus seeds
//! drawn uniformly in the box, and grows from an active list: each active sample tries
//! `attempts` candidates in the spherical shell [r, 2r) around it and retires when none fits.
//! Fixed points are inserted as they are, even when closer than r to each other.

use glam::DVec3;

use karst_geology::rng::Random;

/// How many uniform seeds are tried so that regions far from every fixed point get sampled.
const SEED_TRIES: usize = 64;

/// Poisson-disk samples of minimum distance `radius` in `region` ∩ [lo, hi], starting with
/// `fixed` (returned first, unchanged).
pub fn sample(
    lo: DVec3,
    hi: DVec3,
    radius: f64,
    attempts: u32,
    fixed: &[DVec3],
    region: impl Fn(DVec3) -> bool,
    rng: &mut Random,
) -> Vec<DVec3> {
    let mut grid = Grid::new(lo, hi, radius);
    let mut points: Vec<DVec3> = Vec::new();
    let mut active: Vec<usize> = Vec::new();
    for &p in fixed {
        grid.insert(p, points.len());
        active.push(points.len());
        points.push(p);
    }
    for _ in 0..SEED_TRIES {
        let p = DVec3::new(rng.range(lo.x, hi.x), rng.range(lo.y, hi.y), rng.range(lo.z, hi.z));
        if region(p) && grid.is_free(p, &points) {
            grid.insert(p, points.len());
            active.push(points.len());
            points.push(p);
        }
    }
    while !active.is_empty() {
        let slot = rng.index(active.len());
        let centre = points[active[slot]];
        let found = (0..attempts).find_map(|_| {
            let p = centre + shell_offset(rng, radius);
            let inside = p.cmpge(lo).all() && p.cmple(hi).all() && region(p);
            (inside && grid.is_free(p, &points)).then_some(p)
        });
        match found {
            Some(p) => {
                grid.insert(p, points.len());
                active.push(points.len());
                points.push(p);
            }
            None => {
                active.swap_remove(slot);
            }
        }
    }
    points
}

/// A uniformly random offset in the spherical shell of radii [r, 2r).
fn shell_offset(rng: &mut Random, r: f64) -> DVec3 {
    let z = rng.range(-1.0, 1.0);
    let phi = rng.range(0.0, std::f64::consts::TAU);
    let s = (1.0 - z * z).sqrt();
    // Uniform in volume: r³ uniform in [r³, 8r³).
    let d = (r * r * r * rng.range(1.0, 8.0)).cbrt();
    DVec3::new(s * phi.cos(), s * phi.sin(), z) * d
}

/// Background grid: cell size r/√3, so a cell holds at most one sample of a valid set (fixed
/// points that violate the spacing share cells through the overflow list).
struct Grid {
    lo: DVec3,
    cell: f64,
    dims: [usize; 3],
    cells: Vec<u32>,
    overflow: Vec<usize>,
    radius2: f64,
}

const EMPTY: u32 = u32::MAX;

impl Grid {
    fn new(lo: DVec3, hi: DVec3, radius: f64) -> Self {
        let cell = radius / 3f64.sqrt();
        let n = ((hi - lo) / cell).ceil().max(DVec3::ONE);
        let dims = [n.x as usize + 1, n.y as usize + 1, n.z as usize + 1];
        Grid {
            lo,
            cell,
            dims,
            cells: vec![EMPTY; dims[0] * dims[1] * dims[2]],
            overflow: Vec::new(),
            radius2: radius * radius,
        }
    }

    fn coords(&self, p: DVec3) -> [usize; 3] {
        let c = ((p - self.lo) / self.cell).floor().max(DVec3::ZERO);
        [
            (c.x as usize).min(self.dims[0] - 1),
            (c.y as usize).min(self.dims[1] - 1),
            (c.z as usize).min(self.dims[2] - 1),
        ]
    }

    fn index(&self, [x, y, z]: [usize; 3]) -> usize {
        (z * self.dims[1] + y) * self.dims[0] + x
    }

    fn insert(&mut self, p: DVec3, id: usize) {
        let i = self.index(self.coords(p));
        if self.cells[i] == EMPTY {
            self.cells[i] = id as u32;
        } else {
            self.overflow.push(id);
        }
    }

    fn is_free(&self, p: DVec3, points: &[DVec3]) -> bool {
        let [cx, cy, cz] = self.coords(p);
        let span = |c: usize, n: usize| c.saturating_sub(2)..(c + 3).min(n);
        for z in span(cz, self.dims[2]) {
            for y in span(cy, self.dims[1]) {
                for x in span(cx, self.dims[0]) {
                    let id = self.cells[self.index([x, y, z])];
                    if id != EMPTY && points[id as usize].distance_squared(p) < self.radius2 {
                        return false;
                    }
                }
            }
        }
        self.overflow.iter().all(|&id| points[id].distance_squared(p) >= self.radius2)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn brute_min_distance(points: &[DVec3], skip_fixed: usize) -> f64 {
        let mut best = f64::INFINITY;
        for i in skip_fixed..points.len() {
            for j in 0..i {
                best = best.min(points[i].distance(points[j]));
            }
        }
        best
    }

    #[test]
    fn spacing_and_region_are_respected() {
        let mut rng = Random::stream(1, "test", "poisson");
        let fixed = [DVec3::new(5.0, 5.0, 5.0), DVec3::new(5.5, 5.0, 5.0)];
        let below = |p: DVec3| p.z < 20.0 - 0.2 * p.x;
        let pts = sample(DVec3::ZERO, DVec3::new(60.0, 40.0, 20.0), 4.0, 30, &fixed, below, &mut rng);
        assert_eq!(&pts[..2], &fixed);
        assert!(brute_min_distance(&pts, 2) >= 4.0);
        assert!(pts[2..].iter().all(|p| below(*p)));
        // Maximal: the region holds 60·40·14 = 33600 m³; a maximal Poisson-disk set of r = 4
        // leaves no empty ball of radius 4 (268 m³), so it needs well over 150 points.
        assert!(pts.len() > 150, "{}", pts.len());
    }

    #[test]
    fn same_seed_same_samples() {
        let run = || {
            let mut rng = Random::stream(9, "test", "poisson");
            sample(DVec3::ZERO, DVec3::splat(30.0), 3.0, 30, &[], |_| true, &mut rng)
        };
        assert_eq!(run(), run());
    }
}
