//! Variable-radius Poisson-disk sampling in 3D by dart throwing over a background grid.
//!
//! Two samples p, q must be at least min(r(p), r(q)) apart, r the tabulated radius field: a
//! candidate p therefore only needs the samples within r(p), found in the background grid
//! (cell h = the field's smallest radius, each cell a linked list of its samples).
//!
//! Bridson's algorithm grows one front sample at a time and is hard to make fast; here every
//! grid cell (edge r_min/√3, so that it holds at most one sample) gets one uniform dart per
//! pass, cells visited in eight interleaved parity classes so that no scan direction is
//! favoured (Wei 2008's phase groups). Darts go into the cell's child octants not yet known to
//! be covered: each rejecting sample removes the octants its disk covers entirely. A cell
//! retires when it takes a sample, when all its octants are covered, or after `attempts`
//! consecutive failed darts (it is then covered up to a vanishing fraction). Darts
//! come from one seeded stream in a fixed order: the result is deterministic. Key points are
//! inserted first as they are, even when closer than r to each other; surface samples are darts
//! on the surfaces themselves (see `surfaces.rs`) and go in before the volume's.

use glam::DVec3;

use karst_geology::rng::Random;

use crate::radius::RadiusField;

const NONE: u32 = u32::MAX;

/// Offset (0 or 1 per axis) of child octant `k`.
fn octant(k: u32) -> DVec3 {
    DVec3::new((k & 1) as f64, (k >> 1 & 1) as f64, (k >> 2 & 1) as f64)
}

/// The state of a cell that takes no more darts.
const RETIRED: u8 = u8::MAX;

/// The growing sample set and its background grid.
pub struct Sampler<'a> {
    field: &'a RadiusField,
    /// The field's smallest radius.
    r_min: f64,
    /// The radius when the field is constant (no interpolation needed).
    constant: Option<f64>,
    lo: DVec3,
    cell: f64,
    dims: [usize; 3],
    head: Vec<u32>,
    next: Vec<u32>,
    /// Neighbour cell offsets, nearest first, with the smallest distance between a point of
    /// the centre cell and a point of that cell.
    offsets: Vec<([i32; 3], f64)>,
    pub points: Vec<DVec3>,
    radii: Vec<f32>,
}

impl<'a> Sampler<'a> {
    /// An empty sampler over the box `lo`–`hi`, background cells of `cell` metres.
    pub fn new(field: &'a RadiusField, lo: DVec3, hi: DVec3, cell: f64) -> Self {
        let n = ((hi - lo) / cell).ceil().max(DVec3::ONE);
        let dims = [n.x as usize, n.y as usize, n.z as usize];
        let reach = (field.max() / cell).ceil() as i32;
        let mut offsets = Vec::new();
        for z in -reach..=reach {
            for y in -reach..=reach {
                for x in -reach..=reach {
                    let gap = |d: i32| (d.abs() - 1).max(0) as f64 * cell;
                    let d = (gap(x).powi(2) + gap(y).powi(2) + gap(z).powi(2)).sqrt();
                    if d < field.max() {
                        offsets.push(([x, y, z], d));
                    }
                }
            }
        }
        offsets.sort_by(|a, b| a.1.total_cmp(&b.1).then(a.0.cmp(&b.0)));
        Sampler {
            field,
            r_min: field.min(),
            constant: (field.min() == field.max()).then(|| field.min()),
            lo,
            cell,
            dims,
            offsets,
            head: vec![NONE; dims[0] * dims[1] * dims[2]],
            next: Vec::new(),
            points: Vec::new(),
            radii: Vec::new(),
        }
    }

    pub fn cells(&self) -> usize {
        self.head.len()
    }

    fn coords(&self, p: DVec3) -> [usize; 3] {
        let c = ((p - self.lo) / self.cell).floor().max(DVec3::ZERO);
        [
            (c.x as usize).min(self.dims[0] - 1),
            (c.y as usize).min(self.dims[1] - 1),
            (c.z as usize).min(self.dims[2] - 1),
        ]
    }

    /// Inserts `p` whatever its neighbours (key points).
    fn radius_at(&self, p: DVec3) -> f64 {
        self.constant.unwrap_or_else(|| self.field.at(p))
    }

    pub fn force(&mut self, p: DVec3) {
        let r = self.radius_at(p) as f32;
        let [x, y, z] = self.coords(p);
        let c = (z * self.dims[1] + y) * self.dims[0] + x;
        self.next.push(self.head[c]);
        self.head[c] = self.points.len() as u32;
        self.points.push(p);
        self.radii.push(r);
    }

    /// Inserts `p` when no sample lies closer than min(r(p), r(q)); returns whether it did.
    pub fn try_insert(&mut self, p: DVec3) -> bool {
        let r = self.radius_at(p);
        if self.blocker(p, r).is_none() {
            self.force(p);
            return true;
        }
        false
    }

    /// A sample closer to `p` than min(r, its radius), nearest cells first.
    fn blocker(&self, p: DVec3, r: f64) -> Option<u32> {
        let c = self.coords(p).map(|v| v as i32);
        let dims = self.dims.map(|v| v as i32);
        for &(o, gap) in &self.offsets {
            if gap >= r {
                break;
            }
            let (x, y, z) = (c[0] + o[0], c[1] + o[1], c[2] + o[2]);
            if x < 0 || y < 0 || z < 0 || x >= dims[0] || y >= dims[1] || z >= dims[2] {
                continue;
            }
            let mut id = self.head[((z * dims[1] + y) * dims[0] + x) as usize];
            while id != NONE {
                let q = self.points[id as usize];
                let m = r.min(self.radii[id as usize] as f64);
                if q.distance_squared(p) < m * m {
                    return Some(id);
                }
                id = self.next[id as usize];
            }
        }
        None
    }

    /// Fills `region` with darts, one per live cell per pass, until every cell is occupied,
    /// covered by one sample's disk, or has failed `attempts` times in a row.
    /// `retired(n)` hears how many cells have retired after each pass (for a progress bar).
    pub fn fill_volume(
        &mut self,
        attempts: u32,
        rng: &mut Random,
        region: impl Fn(DVec3) -> bool,
        retired: impl Fn(u64),
    ) {
        // misses[c]: consecutive failed darts of cell c; RETIRED once it is done. One byte per
        // cell is all the state: each pass walks the cells in parity order.
        let mut misses = vec![0u8; self.head.len()];
        let mut children = vec![u8::MAX; self.head.len()];
        let limit = attempts.min(254) as u8;
        let [nx, ny, nz] = self.dims;
        let mut remaining = self.head.len();
        while remaining > 0 {
            for parity in 0..8usize {
                for z in (parity >> 2 & 1..nz).step_by(2) {
                    for y in (parity >> 1 & 1..ny).step_by(2) {
                        for x in (parity & 1..nx).step_by(2) {
                            let c = (z * ny + y) * nx + x;
                            if misses[c] == RETIRED {
                                continue;
                            }
                            let corner = self.lo + DVec3::new(x as f64, y as f64, z as f64) * self.cell;
                            if !self.dart(corner, &mut children[c], rng, &region) {
                                misses[c] += 1;
                                if misses[c] < limit {
                                    continue;
                                }
                            }
                            misses[c] = RETIRED;
                            remaining -= 1;
                        }
                    }
                }
            }
            retired((self.head.len() - remaining) as u64);
        }
    }

    /// Throws one dart in a live child octant of the cell at `corner`; false when it failed
    /// and the cell may still take a sample, true when the cell is done (a sample went in, or
    /// every child is covered). The sample that rejects a dart removes the children its disk
    /// covers entirely (a one-level version of Ebeida et al. 2011's refinement that uses no
    /// search beyond the dart's own).
    fn dart(
        &mut self,
        corner: DVec3,
        children: &mut u8,
        rng: &mut Random,
        region: &impl Fn(DVec3) -> bool,
    ) -> bool {
        let half = 0.5 * self.cell;
        let nth = rng.index(children.count_ones() as usize);
        let child = (0..8u32).filter(|k| *children >> k & 1 == 1).nth(nth).unwrap_or(0);
        let p = corner + (octant(child) + DVec3::new(rng.uniform(), rng.uniform(), rng.uniform())) * half;
        if !region(p) {
            return false;
        }
        match self.blocker(p, self.radius_at(p)) {
            None => {
                self.force(p);
                true
            }
            Some(q) => {
                *children &= !self.covered_children(q, corner);
                *children == 0
            }
        }
    }

    /// Bit k set when sample `q` covers child octant k of the cell at `corner` entirely: every
    /// point p of it is closer to q than min(r(p), r(q)), r(p) bounded below by the field's
    /// smallest radius (or its smallest node value around the cell).
    fn covered_children(&self, q: u32, corner: DVec3) -> u8 {
        let half = 0.5 * self.cell;
        let qp = self.points[q as usize];
        let rq = self.radii[q as usize] as f64;
        let mut reach = rq.min(self.r_min);
        let mut mask = 0u8;
        for k in 0..8u32 {
            let lo = corner + octant(k) * half;
            let far = (qp - lo).abs().max((qp - lo - DVec3::splat(half)).abs()).length();
            if far >= reach && far < rq && reach < rq {
                reach = rq.min(self.field.min_in(corner, corner + self.cell));
            }
            if far < reach {
                mask |= 1 << k;
            }
        }
        mask
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn field(values: impl Fn(DVec3) -> f32) -> RadiusField {
        let size = [13u32, 9, 5];
        let cell = 5.0;
        let mut v = Vec::new();
        for k in 0..size[2] {
            for j in 0..size[1] {
                for i in 0..size[0] {
                    v.push(values(DVec3::new(i as f64, j as f64, k as f64) * cell));
                }
            }
        }
        RadiusField { origin: [0.0; 3], cell, size, values: v }
    }

    fn run(f: &RadiusField, seed: u64) -> Vec<DVec3> {
        let mut rng = Random::stream(seed, "test", "poisson");
        let mut s = Sampler::new(f, DVec3::ZERO, DVec3::new(60.0, 40.0, 20.0), f.min());
        s.force(DVec3::new(5.0, 5.0, 5.0));
        s.force(DVec3::new(5.5, 5.0, 5.0));
        s.fill_volume(12, &mut rng, |p| p.z < 20.0 - 0.2 * p.x, |_| {});
        s.points
    }

    #[test]
    fn variable_spacing_and_region_are_respected() {
        let f = field(|p| 2.0 + p.x as f32 / 30.0);
        let pts = run(&f, 1);
        assert_eq!(&pts[..2], &[DVec3::new(5.0, 5.0, 5.0), DVec3::new(5.5, 5.0, 5.0)]);
        for i in 2..pts.len() {
            assert!(pts[i].z < 20.0 - 0.2 * pts[i].x);
            for j in 0..i {
                let m = f.at(pts[i]).min(f.at(pts[j]));
                assert!(pts[i].distance(pts[j]) >= m, "{} {}", pts[i], pts[j]);
            }
        }
        // Denser where the radius is small: compare the west and east thirds of the region.
        let west = pts.iter().filter(|p| p.x < 20.0).count();
        let east = pts.iter().filter(|p| p.x > 40.0).count();
        assert!(west > 2 * east, "{west} vs {east}");
    }

    #[test]
    fn nearly_maximal_and_deterministic() {
        let f = field(|_| 3.0);
        let pts = run(&f, 5);
        assert_eq!(pts, run(&f, 5));
        // Look for holes: a point of the region farther than r from every sample could still
        // take one. A maximal set has none; dart throwing leaves very few.
        let mut rng = Random::stream(2, "test", "probe");
        let mut holes = 0;
        let probes = 2000;
        for _ in 0..probes {
            let p = DVec3::new(rng.range(0.0, 60.0), rng.range(0.0, 40.0), rng.range(0.0, 20.0));
            if p.z < 20.0 - 0.2 * p.x && pts.iter().all(|q| q.distance(p) >= 3.0) {
                holes += 1;
            }
        }
        assert!(holes * 100 < probes, "{holes} holes in {probes} probes");
    }
}
