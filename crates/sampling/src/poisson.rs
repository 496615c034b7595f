//! Variable-radius Poisson-disk sampling in 3D: parallel, deterministic dart throwing over a
//! background grid.
//!
//! Two samples p, q must be at least min(r(p), r(q)) apart, r the tabulated radius field.
//! The background grid has cells of edge h (the volume's base radius), each a linked list of
//! its samples; a point only conflicts with samples of the cells whose gap to its own cell is
//! below the field's largest radius (`reach` cells per axis).
//!
//! Phase groups (Wei 2008): cells are coloured by their coordinates modulo reach + 1, so that
//! two cells of one colour are more than the largest radius apart and can never conflict.
//! The cells of one colour are processed in parallel; each reads only the samples already in
//! the grid (left by earlier colours) and its own new ones, and draws its darts from a random
//! stream of its own, derived from (seed, pass, cell) by a counter-based generator. The new
//! samples are appended in cell order after each colour: the result does not depend on the
//! number of threads.
//!
//! The region (domain, terrain, no-karst volumes) is tested once per grid vertex and cell
//! centre before the passes: cells with none of their corners and centre inside are skipped.
//! `WARM_PASSES` (one) pass throws one dart per cell (so that the bulk of the samples is
//! spread without a scan order), then one saturation pass fills every cell: of its 27 sub-cells
//! of edge h/3, those that no single neighbouring disk covers entirely are live; darts go into
//! random live sub-cells, and each new sample removes the sub-cells its disk covers (a
//! one-level, cell-local version of Ebeida et al. 2011's refinement), for `ROUNDS` rounds of
//! one dart per live sub-cell. Sub-cells covered by the union of several disks but by none alone
//! stay live and take darts in vain; what is left uncovered after the rounds is small: a tiny
//! fraction of the bedrock is farther than r from every sample after one round, and a second
//! round halves it for a few more samples and markedly more instructions (BENCHMARKS.md,
//! "sampling").
//!
//! Key points are inserted first as they are, even when closer than r to each other; surface
//! samples are darts on the surfaces themselves, in phase groups of their own (see
//! `surfaces.rs`), and go in before the volume's.

use glam::{DVec3, Vec4};
use rayon::prelude::*;

use crate::spacing::SpacingField;

const NONE: u32 = u32::MAX;

/// Passes of one dart per cell before the saturation pass (a second one costs more
/// instructions and leaves as many holes).
const WARM_PASSES: u32 = 1;
/// Rounds of one dart per live sub-cell in the saturation pass (see the module's documentation).
const ROUNDS: u32 = 1;

/// A cheap counter-based random stream (splitmix64 steps from a hashed seed); each cell of
/// each pass has its own, so the darts do not depend on the processing order.
pub(crate) struct CellRng(u64);

fn mix(mut z: u64) -> u64 {
    z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
    z ^ (z >> 31)
}

impl CellRng {
    pub(crate) fn new(key: u64, pass: u32, cell: usize) -> Self {
        CellRng(mix(key ^ mix((cell as u64) << 8 | pass as u64)))
    }

    fn next(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        mix(self.0)
    }

    /// Uniform in [0, 1), 53 bits.
    pub(crate) fn uniform(&mut self) -> f64 {
        (self.next() >> 11) as f64 * (1.0 / (1u64 << 53) as f64)
    }

    fn unit_cube(&mut self) -> DVec3 {
        DVec3::new(self.uniform(), self.uniform(), self.uniform())
    }

    /// Integer in 0..n (multiply-shift; the bias is below 2⁻⁴⁰ for the small n used here).
    fn below(&mut self, n: usize) -> usize {
        ((self.next() as u128 * n as u128) >> 64) as usize
    }
}

/// Per-thread scratch space of the saturation pass (reused from cell to cell).
#[derive(Default)]
struct Scratch {
    /// Samples that may conflict with a point of the cell: (position, radius).
    near: Vec<(DVec3, f64)>,
}

/// The growing sample set and its background grid.
pub struct Sampler<'a> {
    field: &'a SpacingField,
    /// The radius when the field is constant (no interpolation needed).
    constant: Option<f64>,
    lo: DVec3,
    cell: f64,
    dims: [usize; 3],
    /// The field's smallest and largest radii.
    r_min: f64,
    r_max: f64,
    /// Colour period: cells `reach` + 1 apart along an axis never conflict.
    period: usize,
    head: Vec<u32>,
    /// Neighbour cell offsets, nearest first, with the smallest distance between a point of
    /// the centre cell and a point of that cell (below the field's largest radius).
    offsets: Vec<([i32; 3], f64)>,
    /// The same offsets as index deltas, for cells at least `reach` cells from the border.
    deltas: Vec<(isize, f64)>,
    reach: usize,
    /// The samples in insertion order, each with its cell list's link.
    entries: Vec<Entry>,
}

/// A sample of the grid: its position and radius, and the next sample of its cell. One record
/// (half a cache line) rather than three arrays: the neighbour walks, most of the sampler's
/// time, read all three of every sample they visit, in no order the memory can predict.
#[derive(Clone, Copy)]
struct Entry {
    position: DVec3,
    radius: f32,
    next: u32,
}

impl<'a> Sampler<'a> {
    /// An empty sampler over the box `lo`–`hi`, background cells of `cell` metres.
    pub fn new(field: &'a SpacingField, lo: DVec3, hi: DVec3, cell: f64) -> Self {
        let n = ((hi - lo) / cell).ceil().max(DVec3::ONE);
        let dims = [n.x as usize, n.y as usize, n.z as usize];
        let (r_min, r_max) = (field.min(), field.max());
        let reach = (r_max / cell).ceil() as i32;
        let mut offsets = Vec::new();
        for z in -reach..=reach {
            for y in -reach..=reach {
                for x in -reach..=reach {
                    let gap = |d: i32| (d.abs() - 1).max(0) as f64 * cell;
                    let d = (gap(x).powi(2) + gap(y).powi(2) + gap(z).powi(2)).sqrt();
                    if d < r_max {
                        offsets.push(([x, y, z], d));
                    }
                }
            }
        }
        // Nearest first by gap (the walks stop at the first gap too large), then by the distance
        // between the cells' centres: the cell itself, its faces, edges and corners. Which
        // sample rejects a dart does not change the samples (only whether one does), and the
        // nearest cells hold the likely ones, so the darts' tests end sooner.
        let centres = |o: &[i32; 3]| o.iter().map(|c| c * c).sum::<i32>();
        offsets
            .sort_by(|a, b| a.1.total_cmp(&b.1).then(centres(&a.0).cmp(&centres(&b.0))).then(a.0.cmp(&b.0)));
        let deltas = offsets
            .iter()
            .map(|([x, y, z], g)| {
                (*x as isize + dims[0] as isize * (*y as isize + dims[1] as isize * *z as isize), *g)
            })
            .collect();
        Sampler {
            deltas,
            reach: reach as usize,
            field,
            constant: (r_min == r_max).then_some(r_min),
            lo,
            cell,
            dims,
            r_min,
            r_max,
            period: reach as usize + 1,
            offsets,
            head: vec![NONE; dims[0] * dims[1] * dims[2]],
            entries: Vec::new(),
        }
    }

    /// Number of samples so far.
    pub fn count(&self) -> usize {
        self.entries.len()
    }

    /// The samples' positions, in insertion order.
    pub fn into_points(self) -> Vec<DVec3> {
        self.entries.into_iter().map(|e| e.position).collect()
    }

    /// The field's smallest radius.
    pub fn min_radius(&self) -> f64 {
        self.r_min
    }

    /// Units of work of `fill_volume` (cells times passes), for a progress bar.
    pub fn work(&self) -> usize {
        self.head.len() * (WARM_PASSES as usize + 1)
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

    /// The field's largest radius.
    pub fn max_radius(&self) -> f64 {
        self.r_max
    }

    pub(crate) fn radius_at(&self, p: DVec3) -> f64 {
        self.constant.unwrap_or_else(|| self.field.at(p))
    }

    fn push(&mut self, c: usize, p: DVec3, r: f32) {
        let next = self.head[c];
        self.head[c] = self.entries.len() as u32;
        self.entries.push(Entry { position: p, radius: r, next });
    }

    /// Inserts `p` whatever its neighbours (key points).
    pub fn force(&mut self, p: DVec3) {
        let r = self.radius_at(p) as f32;
        let c = self.index(self.coords(p));
        self.push(c, p, r);
    }

    /// Appends the samples of the cells that meet the box lo–hi grown by the largest radius,
    /// as (position, radius): every sample that may conflict with a point of the box.
    pub(crate) fn gather(&self, lo: DVec3, hi: DVec3, out: &mut Vec<(DVec3, f64)>) {
        let grow = DVec3::splat(self.r_max);
        let (a, b) = (self.coords(lo - grow), self.coords(hi + grow));
        for z in a[2]..=b[2] {
            for y in a[1]..=b[1] {
                for x in a[0]..=b[0] {
                    out.extend(
                        self.cell_samples(self.index([x, y, z])).map(|e| (e.position, e.radius as f64)),
                    );
                }
            }
        }
    }

    /// Inserts samples found elsewhere (already checked against the grid), in order.
    pub(crate) fn extend(&mut self, found: impl IntoIterator<Item = (DVec3, f32)>) {
        for (p, r) in found {
            let c = self.index(self.coords(p));
            self.push(c, p, r);
        }
    }

    /// The samples of cell `c` (index), newest first: its linked list. (The list ends at
    /// [`NONE`], past every sample, so one lookup both ends the walk and reads the sample.)
    #[inline]
    fn cell_samples(&self, c: usize) -> impl Iterator<Item = &Entry> {
        let mut id = self.head[c];
        std::iter::from_fn(move || {
            let e = self.entries.get(id as usize)?;
            id = e.next;
            Some(e)
        })
    }

    /// The samples of the cells around cell `c` (coordinates) closer than `gap` to it.
    fn neighbours(&self, c: [usize; 3], gap: f64, mut visit: impl FnMut(&Entry) -> bool) {
        let k = self.reach;
        if (0..3).all(|a| c[a] >= k && c[a] + k < self.dims[a]) {
            let centre = self.index(c) as isize;
            for &(delta, g) in &self.deltas {
                if g >= gap {
                    break;
                }
                if !self.cell_samples((centre + delta) as usize).all(&mut visit) {
                    return;
                }
            }
            return;
        }
        let c = c.map(|v| v as i32);
        let dims = self.dims.map(|v| v as i32);
        for &(o, g) in &self.offsets {
            if g >= gap {
                break;
            }
            let (x, y, z) = (c[0] + o[0], c[1] + o[1], c[2] + o[2]);
            if x < 0 || y < 0 || z < 0 || x >= dims[0] || y >= dims[1] || z >= dims[2] {
                continue;
            }
            if !self.cell_samples(((z * dims[1] + y) * dims[0] + x) as usize).all(&mut visit) {
                return;
            }
        }
    }

    /// True when a sample of the grid lies closer to `p` than min(r, its radius).
    fn blocked(&self, p: DVec3, r: f64) -> bool {
        let mut hit = false;
        self.neighbours(self.coords(p), r, |e| {
            let m = r.min(e.radius as f64);
            hit = e.position.distance_squared(p) < m * m;
            !hit
        });
        hit
    }

    /// Fills `region` with samples: `WARM_PASSES` passes of one dart per cell, then one pass
    /// that saturates every cell (see the module's documentation). `key` seeds every cell's
    /// random stream. `done(n)` hears how many units of `work()` are done.
    pub fn fill_volume(&mut self, key: u64, region: impl Fn(DVec3) -> bool + Sync, done: impl Fn(u64)) {
        let [nx, ny, nz] = self.dims;
        let k = self.period;
        let mut finished = 0u64;
        let inside = self.region_bits(&region);
        for pass in 0..=WARM_PASSES {
            let saturate = pass == WARM_PASSES;
            for colour in 0..k * k * k {
                let (cx, cy, cz) = (colour % k, colour / k % k, colour / (k * k));
                let rows: Vec<(usize, usize)> =
                    (cz..nz).step_by(k).flat_map(|z| (cy..ny).step_by(k).map(move |y| (z, y))).collect();
                let this = &*self;
                let found: Vec<Vec<(u32, DVec3, f32)>> = rows
                    .par_iter()
                    .map_init(Scratch::default, |scratch, &(z, y)| {
                        let mut out = Vec::new();
                        for x in (cx..nx).step_by(k) {
                            let c = [x, y, z];
                            let mut rng = CellRng::new(key, pass, this.index(c));
                            if saturate {
                                this.saturate(c, &mut rng, &region, &inside, scratch, &mut out);
                            } else if inside.some(this.index(c)) {
                                this.warm_dart(c, &mut rng, &region, &mut out);
                            }
                        }
                        out.shrink_to_fit();
                        out
                    })
                    .collect();
                for (c, p, r) in found.into_iter().flatten() {
                    self.push(c as usize, p, r);
                }
                finished += (rows.len() * nx.saturating_sub(cx).div_ceil(k)) as u64;
                done(finished);
            }
        }
    }

    /// Which cells have some or all of their 8 corners and centre in the region: each grid
    /// vertex and cell centre is tested once (in parallel by layers of cells), not once per
    /// cell that shares it.
    fn region_bits(&self, region: &(impl Fn(DVec3) -> bool + Sync)) -> RegionBits {
        let [nx, ny, nz] = self.dims;
        let vertices = |z: usize| -> Vec<bool> {
            let mut layer = Vec::with_capacity((nx + 1) * (ny + 1));
            for y in 0..=ny {
                for x in 0..=nx {
                    layer.push(region(self.corner([x, y, z])));
                }
            }
            layer
        };
        let vertex: Vec<Vec<bool>> = (0..=nz).into_par_iter().map(vertices).collect();
        // Per layer of cells: bit 0 some probe inside, bit 1 all of them.
        let layers: Vec<Vec<u8>> = (0..nz)
            .into_par_iter()
            .map(|z| {
                let (below, above) = (&vertex[z], &vertex[z + 1]);
                let mut classes = Vec::with_capacity(nx * ny);
                for y in 0..ny {
                    for x in 0..nx {
                        let v = |l: &[bool], dx: usize, dy: usize| l[(y + dy) * (nx + 1) + x + dx] as usize;
                        let centre = self.corner([x, y, z]) + DVec3::splat(0.5 * self.cell);
                        let n = region(centre) as usize
                            + [below, above]
                                .iter()
                                .map(|l| v(l, 0, 0) + v(l, 1, 0) + v(l, 0, 1) + v(l, 1, 1))
                                .sum::<usize>();
                        classes.push((n > 0) as u8 | ((n == 9) as u8) << 1);
                    }
                }
                classes
            })
            .collect();
        let n = nx * ny * nz;
        let mut bits = RegionBits { some: vec![0; n.div_ceil(64)], all: vec![0; n.div_ceil(64)] };
        for (i, b) in layers.into_iter().flatten().enumerate() {
            bits.some[i / 64] |= ((b & 1) as u64) << (i % 64);
            bits.all[i / 64] |= ((b >> 1) as u64) << (i % 64);
        }
        bits
    }

    fn corner(&self, [x, y, z]: [usize; 3]) -> DVec3 {
        self.lo + DVec3::new(x as f64, y as f64, z as f64) * self.cell
    }

    /// One uniform dart in cell `c`.
    fn warm_dart(
        &self,
        c: [usize; 3],
        rng: &mut CellRng,
        region: &impl Fn(DVec3) -> bool,
        out: &mut Vec<(u32, DVec3, f32)>,
    ) {
        let p = self.corner(c) + rng.unit_cube() * self.cell;
        if !region(p) {
            return;
        }
        let r = self.radius_at(p);
        if !self.blocked(p, r) {
            out.push((self.index(c) as u32, p, r as f32));
        }
    }

    /// Fills cell `c` up to a vanishing uncovered part (see the module's documentation).
    fn saturate(
        &self,
        c: [usize; 3],
        rng: &mut CellRng,
        region: &impl Fn(DVec3) -> bool,
        inside: &RegionBits,
        scratch: &mut Scratch,
        out: &mut Vec<(u32, DVec3, f32)>,
    ) {
        let h = self.cell;
        let corner = self.corner(c);
        // The region is resolved to the cell: a cell none of whose corners and centre is in
        // the region is skipped; in a cell where some are not, every live sub-cell must have
        // one of its own in the region.
        let ci = self.index(c);
        if !inside.some(ci) {
            return;
        }
        let boundary = !inside.all(ci);
        let touches = |lo: DVec3, s: f64| !boundary || box_probes(lo, s).any(region);
        // Every point x of the cell has r(x) ≥ floor.
        let floor = self.constant.unwrap_or_else(|| self.field.min_in(corner, corner + DVec3::splat(h)));
        let near = &mut scratch.near;
        near.clear();
        // Only the samples nearer the cell than their own radius can reject a dart in it or
        // cover part of it (about a quarter of the 27 cells' samples are farther).
        let far = corner + DVec3::splat(h);
        self.neighbours(c, self.r_max, |e| {
            let (q, rq) = (e.position, e.radius as f64);
            if (corner - q).max(q - far).max(DVec3::ZERO).length_squared() < rq * rq {
                near.push((q, rq));
            }
            true
        });
        let cell = self.index(c) as u32;
        // Throws a dart at `p`: the index in `near` of the sample that rejects it, or of the
        // new sample. (The neighbours first: most darts are rejected, and the region costs
        // more.)
        let mut dart = |p: DVec3, near: &mut Vec<(DVec3, f64)>| -> Option<usize> {
            let r = self.radius_at(p);
            let blocker = near.iter().position(|(q, rq)| {
                let m = r.min(*rq);
                q.distance_squared(p) < m * m
            });
            match blocker {
                Some(b) => Some(b),
                None if region(p) => {
                    out.push((cell, p, r as f32));
                    near.push((p, r));
                    Some(near.len() - 1)
                }
                None => None,
            }
        };
        // The 27 sub-cells, as a bit set.
        let s1 = h / 3.0;
        let sub = |k: u32| corner + SUB27[k as usize] * s1;
        let mut mask: u32 = (1 << 27) - 1;
        let gathered = near.len();
        for &(q, rq) in near.iter() {
            mask &= !cover27(q, rq.min(floor), corner, s1);
        }
        if boundary {
            for k in 0..27 {
                if mask >> k & 1 == 1 && !touches(sub(k), s1) {
                    mask &= !(1 << k);
                }
            }
        }
        // Where the radius is below the sub-cells' diagonal (near surfaces with a small
        // `surface_radius`), no disk covers a sub-cell and a sub-cell holds several samples:
        // more rounds, in proportion to how many fit.
        let crowd = (s1 * 3f64.sqrt() / floor).powi(3).ceil().clamp(1.0, 64.0) as u32;
        for _ in 0..ROUNDS * crowd {
            for _ in 0..mask.count_ones() {
                if mask == 0 {
                    return;
                }
                let mut m = mask;
                for _ in 0..rng.below(mask.count_ones() as usize) {
                    m &= m - 1;
                }
                let p = sub(m.trailing_zeros()) + rng.unit_cube() * s1;
                // The disks of the samples gathered first are already out of the mask.
                if let Some(b) = dart(p, near).filter(|&b| b >= gathered) {
                    let (q, rq) = near[b];
                    mask &= !cover27(q, rq.min(floor), corner, s1);
                }
            }
        }
    }
}

/// Per cell (by index), whether some or all of its 8 corners and centre are in the region.
struct RegionBits {
    some: Vec<u64>,
    all: Vec<u64>,
}

impl RegionBits {
    fn some(&self, i: usize) -> bool {
        self.some[i / 64] >> (i % 64) & 1 == 1
    }

    fn all(&self, i: usize) -> bool {
        self.all[i / 64] >> (i % 64) & 1 == 1
    }
}

/// Sub-cell k of a 3 × 3 × 3 block is at (k mod 3, ⌊k/3⌋ mod 3, ⌊k/9⌋) sub-cell edges from the
/// block's corner (a table: the divisions cost more than the dart they place).
const SUB27: [DVec3; 27] = {
    let mut t = [DVec3::ZERO; 27];
    let mut k = 0;
    while k < 27 {
        t[k] = DVec3::new((k % 3) as f64, (k / 3 % 3) as f64, (k / 9) as f64);
        k += 1;
    }
    t
};

/// The eight corners and the centre of the box of edge `s` at `lo`.
fn box_probes(lo: DVec3, s: f64) -> impl Iterator<Item = DVec3> {
    (0..8)
        .map(move |k| lo + DVec3::new((k & 1) as f64, (k >> 1 & 1) as f64, (k >> 2 & 1) as f64) * s)
        .chain([lo + DVec3::splat(0.5 * s)])
}

/// Bit i + 3j + 9k set when the disk of radius `r` around `q` covers the sub-cell (i, j, k)
/// of edge `s` of the 3 × 3 × 3 block at `lo` entirely.
#[inline]
fn cover27(q: DVec3, r: f64, lo: DVec3, s: f64) -> u32 {
    let r2 = r * r;
    // Along each axis, the far side of any sub-cell is at least the gap to the block plus s,
    // or s/2 when q is within the block's slab.
    let gap = (lo - q).max(q - lo - DVec3::splat(3.0 * s));
    let least = DVec3::select(gap.cmpgt(DVec3::ZERO), gap + DVec3::splat(s), DVec3::splat(0.5 * s));
    if least.length_squared() >= r2 {
        return 0;
    }
    // Four lanes at once, in f32 relative to the block (an error of 1e-7 r only decides
    // whether a sliver of that width is left to darts).
    let d = q - lo;
    let far = |c: f64| {
        let a = Vec4::new(c as f32, (c - s) as f32, (c - 2.0 * s) as f32, (c - 3.0 * s) as f32).abs();
        let m = Vec4::new(a.x.max(a.y), a.y.max(a.z), a.z.max(a.w), f32::INFINITY);
        m * m
    };
    let (fx, fy, fz) = (far(d.x), far(d.y), far(d.z));
    let below = Vec4::splat(r2 as f32);
    let mut m = 0;
    for k in 0..3 {
        for j in 0..3 {
            let yz = fy[j] + fz[k];
            m |= ((fx + Vec4::splat(yz)).cmplt(below).bitmask() & 7) << (3 * (j + 3 * k));
        }
    }
    m
}

#[cfg(test)]
mod tests {
    use super::*;
    use karst_scene::rng::Random;

    fn field(values: impl Fn(DVec3) -> f32) -> SpacingField {
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
        SpacingField { origin: [0.0; 3], cell, size, values: v }
    }

    fn run(f: &SpacingField, seed: u64) -> Vec<DVec3> {
        let mut s = Sampler::new(f, DVec3::ZERO, DVec3::new(60.0, 40.0, 20.0), f.min());
        s.force(DVec3::new(5.0, 5.0, 5.0));
        s.force(DVec3::new(5.5, 5.0, 5.0));
        s.fill_volume(seed, |p| p.z < 20.0 - 0.2 * p.x, |_| {});
        s.into_points()
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
