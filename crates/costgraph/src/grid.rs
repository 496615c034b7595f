//! Exact k-nearest-neighbour queries on a uniform grid of cells.
//!
//! The points are bucketed into cubic cells holding a few points each (counting sort, cells in
//! x-fastest order, each point's coordinates copied next to its cell's so that a row of cells
//! is one contiguous run). A query gathers every point within a search radius, visiting only
//! the cells whose box reaches into that ball; when at least k points are inside, the k
//! nearest of them are the k nearest of all. The radius is guessed from the previous query's
//! k-th distance (queries run in Morton order, so neighbouring queries see similar densities)
//! and grown by half when the ball holds fewer than k points.
//!
//! Distances are the f64 squared distances of the input points and ties go to the smaller
//! index, so the result is the exact k nearest (no tolerance), independent of the query order,
//! of the radius guesses and of the thread count. kiddo's `ImmutableKdTree` (used before) ran
//! on f32 coordinates and picked a wrong k-th neighbour in about 2 rows in 100,000 near-ties
//! (the bench's uniform points); it also took more instructions per query (BENCHMARKS.md).

/// Wanted points per cell: small cells fit the searched ball closely, larger ones cost fewer
/// cell visits.
const POINTS_PER_CELL: f64 = 6.0;

pub struct Grid<'a> {
    points: &'a [[f64; 3]],
    lo: [f64; 3],
    cell: f64,
    dims: [usize; 3],
    /// `starts[c]..starts[c + 1]` are the entries of cell c in `sorted`.
    starts: Vec<u32>,
    /// (coordinates, index) of every point, cell by cell.
    sorted: Vec<([f64; 3], u32)>,
    /// Safety margin on the stopping bound, metres: cell membership and distances are
    /// rounded, so the bound is taken slightly short (searching a little more, never less).
    margin: f64,
}

/// The smallest box [lo, hi] holding `points` (inverted, ±∞, when there are none).
pub fn bounds(points: &[[f64; 3]]) -> ([f64; 3], [f64; 3]) {
    let mut lo = [f64::INFINITY; 3];
    let mut hi = [f64::NEG_INFINITY; 3];
    for p in points {
        for axis in 0..3 {
            lo[axis] = lo[axis].min(p[axis]);
            hi[axis] = hi[axis].max(p[axis]);
        }
    }
    (lo, hi)
}

impl<'a> Grid<'a> {
    /// Buckets `points` for queries of `k` neighbours.
    pub fn new(points: &'a [[f64; 3]]) -> Self {
        let (lo, hi) = bounds(points);
        let span: [f64; 3] = std::array::from_fn(|a| (hi[a] - lo[a]).max(0.0));
        let wanted_cells = (points.len() as f64 / POINTS_PER_CELL).max(1.0);
        let cell = cell_size(span, wanted_cells);
        let dims: [usize; 3] = std::array::from_fn(|a| ((span[a] / cell).floor() as usize + 1).max(1));
        let mut grid = Grid {
            points,
            lo,
            cell,
            dims,
            starts: Vec::new(),
            sorted: Vec::new(),
            margin: 1e-9
                * (span.iter().fold(0.0, |m: f64, s| m.max(*s))
                    + lo.iter().chain(&hi).fold(0.0, |m: f64, v| m.max(v.abs()))),
        };
        let cells = dims[0] * dims[1] * dims[2];
        let mut counts = vec![0u32; cells + 1];
        let keys: Vec<u32> = points.iter().map(|p| grid.cell_index(grid.cell_of(p)) as u32).collect();
        for &c in &keys {
            counts[c as usize + 1] += 1;
        }
        for c in 0..cells {
            counts[c + 1] += counts[c];
        }
        let mut next = counts.clone();
        let mut sorted = vec![([0.0; 3], 0u32); points.len()];
        for (i, &c) in keys.iter().enumerate() {
            sorted[next[c as usize] as usize] = (points[i], i as u32);
            next[c as usize] += 1;
        }
        grid.starts = counts;
        grid.sorted = sorted;
        grid
    }

    fn cell_of(&self, p: &[f64; 3]) -> [usize; 3] {
        std::array::from_fn(|a| (((p[a] - self.lo[a]) / self.cell).max(0.0) as usize).min(self.dims[a] - 1))
    }

    fn cell_index(&self, c: [usize; 3]) -> usize {
        (c[2] * self.dims[1] + c[1]) * self.dims[0] + c[0]
    }

    /// A first search radius for `k` neighbours: the radius of the ball holding 1.5 k points
    /// at the mean density of the points' box (axes of zero span count as one cell thick).
    pub fn initial_radius(&self, k: usize) -> f64 {
        let volume: f64 = (0..3).map(|a| self.dims[a] as f64 * self.cell).product();
        let density = self.points.len() as f64 / volume;
        (1.5 * k as f64 * 3.0 / (4.0 * std::f64::consts::PI * density)).cbrt()
    }

    /// The `k` nearest other points of point `i` within squared distance `max2`, nearest
    /// first, ties by index, as [`key`]s in `out` (cleared first).
    ///
    /// `radius` is a guess of the search radius, updated for the next query (queries close in
    /// space need similar radii): every point within it is gathered; when fewer than `k` are
    /// found (and the radius is below the maximum length and the grid) it grows by half and
    /// the search is redone. The guess changes the work, never the result.
    pub fn nearest(&self, i: usize, k: usize, max2: f64, radius: &mut f64, out: &mut Vec<u64>) {
        let p = self.points[i];
        loop {
            out.clear();
            let limit = (*radius * *radius).min(max2);
            self.scan_ball(i, &p, limit, out);
            let everything = self.covers_grid(&p, *radius);
            if out.len() >= k || limit >= max2 || everything {
                break;
            }
            *radius *= 1.5;
        }
        if out.len() > 2 * k {
            keep_the_least(out, k);
        }
        out.sort_unstable();
        self.order_near_ties(&p, out);
        out.truncate(k);
        if out.len() == k {
            // Next guess: 10 % beyond this k-th distance (never below half a cell).
            let kth = distance2(&p, &self.points[index(out[k - 1]) as usize]);
            *radius = (1.1 * kth.sqrt()).max(0.5 * self.cell);
        }
    }

    /// Sorts every run of `keys` (sorted) that share their rounded distance by the exact
    /// distances to `p`, then by index: the order of the exact squared distances, ties by index.
    fn order_near_ties(&self, p: &[f64; 3], keys: &mut [u64]) {
        let exact = |c: &u64| (distance2(p, &self.points[index(*c) as usize]).to_bits(), index(*c));
        for run in keys.chunk_by_mut(|a, b| a >> 32 == b >> 32).filter(|run| run.len() > 1) {
            run.sort_unstable_by_key(exact);
        }
    }

    /// True when the ball of `radius` around `p` contains the whole grid box.
    fn covers_grid(&self, p: &[f64; 3], radius: f64) -> bool {
        (0..3).all(|a| {
            let hi = self.lo[a] + self.dims[a] as f64 * self.cell;
            p[a] - radius <= self.lo[a] && p[a] + radius >= hi
        })
    }

    /// Adds every point other than `i` within squared distance `limit` of `p`, scanning the
    /// cells whose box is within that distance.
    fn scan_ball(&self, i: usize, p: &[f64; 3], limit: f64, out: &mut Vec<u64>) {
        let reach = limit.sqrt() + self.margin;
        let range = |a: usize| {
            let cell = |v: f64| (((v - self.lo[a]) / self.cell).max(0.0) as usize).min(self.dims[a] - 1);
            (cell(p[a] - reach), cell(p[a] + reach))
        };
        let ((x0, x1), (y0, y1), (z0, z1)) = (range(0), range(1), range(2));
        for z in z0..=z1 {
            let gz = self.gap(p[2], z, 2);
            for y in y0..=y1 {
                let gy = self.gap(p[1], y, 1);
                let base = gz * gz + gy * gy;
                if base <= limit {
                    self.scan_cells(i, p, [x0, x1], (y, z), (base, limit), out);
                }
            }
        }
    }

    /// Scans the cells x0..=x1 of row (y, z) (`base`: squared distance from `p` to the row's
    /// y and z slabs), skipping the cells whose box is farther than `limit` (squared) and
    /// keeping the points within it.
    fn scan_cells(
        &self,
        i: usize,
        p: &[f64; 3],
        [x0, x1]: [usize; 2],
        (y, z): (usize, usize),
        (base, limit): (f64, f64),
        out: &mut Vec<u64>,
    ) {
        let row = (z * self.dims[1] + y) * self.dims[0];
        let mut x = x0;
        while x <= x1 {
            // Extend a run of consecutive cells near enough to scan.
            let gx = self.gap(p[0], x, 0);
            if base + gx * gx > limit {
                x += 1;
                continue;
            }
            let start = x;
            while x < x1 {
                let g = self.gap(p[0], x + 1, 0);
                if base + g * g > limit {
                    break;
                }
                x += 1;
            }
            let from = self.starts[row + start] as usize;
            let to = self.starts[row + x + 1] as usize;
            gather_within(&self.sorted[from..to], (i, p), limit, out);
            x += 1;
        }
    }

    /// Distance along `axis` from coordinate `v` to cell `cell`'s slab (0 inside it).
    fn gap(&self, v: f64, cell: usize, axis: usize) -> f64 {
        let lo = self.lo[axis] + cell as f64 * self.cell;
        let hi = lo + self.cell;
        ((lo - v).max(v - hi) - self.margin).max(0.0)
    }
}

/// Appends the [`key`] of every entry of `run` other than point `i` within squared distance
/// `limit` of `p`. Without a branch per entry: every key is written, and the end of `out`
/// moves past those that qualify (about one in three does, at random, so a branch would be
/// mispredicted often).
#[inline]
fn gather_within(run: &[([f64; 3], u32)], (i, p): (usize, &[f64; 3]), limit: f64, out: &mut Vec<u64>) {
    let mut end = out.len();
    out.resize(end + run.len(), 0);
    for &(q, j) in run {
        let d2 = distance2(p, &q);
        out[end] = key(d2, j);
        end += usize::from((d2 <= limit) & (j as usize != i));
    }
    out.truncate(end);
}

/// Keeps in `keys` (unsorted, more than `k`) the `k` least in their order and every other
/// that shares the rounded distance of the k-th (whose exact distance may be smaller).
fn keep_the_least(keys: &mut Vec<u64>, k: usize) {
    let (_, &mut kth, rest) = keys.select_nth_unstable(k - 1);
    let tied = rest.iter().filter(|&&c| c >> 32 == kth >> 32).count();
    if tied > 0 {
        // Move the tied ones right after the k least (their order is settled later).
        let mut at = k;
        for n in k..keys.len() {
            if keys[n] >> 32 == kth >> 32 {
                keys.swap(at, n);
                at += 1;
            }
        }
    }
    keys.truncate(k + tied);
}

/// A candidate as one sortable number: the bits of its squared distance rounded to f32 (≥ 0,
/// so they order as the values do; rounding to nearest never inverts two distances, it may
/// only make them equal), then its index. Half the width of the exact (f64, index) pair, so
/// the sort of the candidates, the largest part of a query after the distances, moves and
/// compares half the bytes; the candidates that share a rounded distance (a few queries in
/// 10,000) are put in exact order afterwards ([`Grid::order_near_ties`]).
fn key(d2: f64, j: u32) -> u64 {
    (u64::from((d2 as f32).to_bits()) << 32) | u64::from(j)
}

/// The index of a candidate [`key`].
pub fn index(key: u64) -> u32 {
    key as u32
}

/// The cell edge for about `wanted` cells over a box of size `span` (axes of zero span count
/// as one cell): bisection on the edge, so thin (planar) point sets get sensible cells too.
fn cell_size(span: [f64; 3], wanted: f64) -> f64 {
    let largest = span.iter().fold(0.0, |m: f64, s| m.max(*s));
    if largest <= 0.0 {
        return 1.0;
    }
    let cells = |h: f64| span.iter().map(|s| (s / h).floor() + 1.0).product::<f64>();
    let (mut small, mut big) = (largest * 1e-7, largest * 2.0);
    for _ in 0..60 {
        let mid = (small * big).sqrt();
        if cells(mid) > wanted { small = mid } else { big = mid }
    }
    big
}

pub fn distance2(a: &[f64; 3], b: &[f64; 3]) -> f64 {
    (a[0] - b[0]).powi(2) + (a[1] - b[1]).powi(2) + (a[2] - b[2]).powi(2)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn brute(points: &[[f64; 3]], i: usize, k: usize, max2: f64) -> Vec<u32> {
        let mut all: Vec<(u64, u32)> = (0..points.len())
            .filter(|&j| j != i)
            .map(|j| (distance2(&points[i], &points[j]).to_bits(), j as u32))
            .filter(|&(d2, _)| f64::from_bits(d2) <= max2)
            .collect();
        all.sort_unstable();
        all.iter().take(k).map(|&(_, j)| j).collect()
    }

    fn check(points: &[[f64; 3]], k: usize, max_length: f64) {
        let grid = Grid::new(points);
        let max2 = max_length * max_length;
        let mut radius = grid.initial_radius(k);
        let mut out = Vec::new();
        for i in 0..points.len() {
            grid.nearest(i, k, max2, &mut radius, &mut out);
            let got: Vec<u32> = out.iter().map(|&c| index(c)).collect();
            assert_eq!(got, brute(points, i, k, max2), "point {i} of {}, k {k}", points.len());
        }
    }

    #[test]
    fn exact_on_uniform_planar_linear_and_clustered_points() {
        let mut state = 99u64;
        let mut next = || {
            state ^= state << 13;
            state ^= state >> 7;
            state ^= state << 17;
            (state >> 11) as f64 / (1u64 << 53) as f64
        };
        let uniform: Vec<[f64; 3]> = (0..800).map(|_| [next() * 50.0, next() * 80.0, next() * 5.0]).collect();
        let planar: Vec<[f64; 3]> = (0..600).map(|_| [next() * 100.0, next() * 100.0, 7.0]).collect();
        let line: Vec<[f64; 3]> = (0..300).map(|i| [i as f64 * 0.5, 3.0, -2.0]).collect();
        // Two dense clusters far apart, with repeated distances (a lattice) and a lone point.
        let mut clustered: Vec<[f64; 3]> =
            (0..343).map(|i| [(i % 7) as f64, ((i / 7) % 7) as f64, (i / 49) as f64]).collect();
        clustered.extend((0..200).map(|_| [1000.0 + next(), 1000.0 + next(), next()]));
        clustered.push([500.0, -300.0, 20.0]);
        for (points, k) in [(&uniform, 1), (&uniform, 17), (&planar, 40), (&line, 9), (&clustered, 30)] {
            check(points, k, f64::INFINITY);
        }
        check(&uniform, 25, 6.0);
        check(&clustered, 60, 1.5);
        check(&line[..3], 5, f64::INFINITY);
    }

    #[test]
    fn exact_when_distances_differ_below_f32_resolution() {
        // A query at the origin among points on the unit sphere whose distances differ in the
        // last bits of an f64 only, the nearest with the larger indices: the candidates' keys
        // tie and the exact order must come from the distances. 40 candidates for k = 5 take
        // the path that selects before sorting.
        let mut points = vec![[0.0, 0.0, 0.0]];
        for n in 0..40 {
            let angle = n as f64 * 0.157;
            let r = 1.0 + (40 - n) as f64 * 3e-15;
            points.push([r * angle.cos(), r * angle.sin(), 0.0]);
        }
        let grid = Grid::new(&points);
        let mut out = Vec::new();
        for k in [1, 5, 17] {
            let mut radius = 2.0;
            grid.nearest(0, k, f64::INFINITY, &mut radius, &mut out);
            let got: Vec<u32> = out.iter().map(|&c| index(c)).collect();
            assert_eq!(got, brute(&points, 0, k, f64::INFINITY), "k {k}");
            assert_eq!(got[0], 40, "k {k}");
        }
        check(&points, 5, f64::INFINITY);
    }
}
