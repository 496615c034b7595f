//! The area of a station's open region: the cells of a square lattice in the station's plane,
//! centred on the measured point, flooded from it through open cells (4-connected), so that
//! another passage crossing the plane nearby does not count.

use glam::DVec3;

/// Cells along each side of the lattice.
const CELLS: usize = 40;

/// Area, m², of the open region of the plane spanned by the unit vectors `u`, `v` that holds
/// `centre`, within a square of side `side` centred on it; `cave` is negative inside and
/// 1-Lipschitz (its magnitude may be less than the distance to its zero set, never more).
pub fn open_area(cave: &impl Fn(DVec3) -> f64, centre: DVec3, [u, v]: [DVec3; 2], side: f64) -> f64 {
    let cell = side / CELLS as f64;
    let at = |i: usize, j: usize| {
        let x = (i as f64 + 0.5) * cell - side / 2.0;
        let y = (j as f64 + 0.5) * cell - side / 2.0;
        centre + u * x + v * y
    };
    let open = signs(&|i, j| cave(at(i, j)), cell);
    let start = (CELLS / 2) * CELLS + CELLS / 2;
    if !open[start] {
        return 0.0;
    }
    let mut seen = vec![false; CELLS * CELLS];
    let mut stack = vec![start];
    seen[start] = true;
    let mut count = 0usize;
    while let Some(k) = stack.pop() {
        count += 1;
        let (i, j) = (k % CELLS, k / CELLS);
        let neighbours = [
            (i > 0).then(|| k - 1),
            (i + 1 < CELLS).then(|| k + 1),
            (j > 0).then(|| k - CELLS),
            (j + 1 < CELLS).then(|| k + CELLS),
        ];
        for n in neighbours.into_iter().flatten() {
            if open[n] && !seen[n] {
                seen[n] = true;
                stack.push(n);
            }
        }
    }
    count as f64 * cell * cell
}

/// Coarsest spacing, in cells, of the points evaluated first by [`signs`].
const COARSEST: usize = 16;

/// Whether each cell's centre is open (`value(i, j)` < 0), from as few values as the bound
/// allows: a value v at a point decides the sign of every point nearer than |v| (the field is
/// 1-Lipschitz), so the points are visited coarse to fine (every [`COARSEST`]-th, then every
/// half as many...) and each value read marks the disc it decides. The result is the sign of
/// every point's own value.
fn signs(value: &impl Fn(usize, usize) -> f64, cell: f64) -> Vec<bool> {
    let mut known: Vec<Option<bool>> = vec![None; CELLS * CELLS];
    let mut step = COARSEST;
    while step >= 1 {
        for j in (0..CELLS).step_by(step) {
            for i in (0..CELLS).step_by(step) {
                if known[j * CELLS + i].is_none() {
                    let v = value(i, j);
                    mark(&mut known, [i, j], v < 0.0, v.abs() * DECIDED / cell);
                }
            }
        }
        step /= 2;
    }
    known.into_iter().map(|k| k == Some(true)).collect()
}

/// The share of a value's magnitude trusted as the radius it decides (a margin for the
/// rounding of the points' positions).
const DECIDED: f64 = 0.999;

/// Sets `open` at (i, j) and at every cell centre nearer to it than `radius` cells.
fn mark(known: &mut [Option<bool>], [i, j]: [usize; 2], open: bool, radius: f64) {
    known[j * CELLS + i] = Some(open);
    let reach = radius.ceil().min(CELLS as f64) as usize;
    for b in j.saturating_sub(reach)..(j + reach + 1).min(CELLS) {
        for a in i.saturating_sub(reach)..(i + reach + 1).min(CELLS) {
            let (di, dj) = (a.abs_diff(i) as f64, b.abs_diff(j) as f64);
            if di * di + dj * dj < radius * radius {
                known[b * CELLS + a] = Some(open);
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_area_of_a_disc_and_not_of_its_neighbour() {
        let (u, v) = (DVec3::Y, DVec3::Z);
        let cave = |p: DVec3| {
            let a = DVec3::new(0.0, p.y, p.z).length() - 2.0;
            let b = DVec3::new(0.0, p.y - 4.5, p.z).length() - 2.0;
            a.min(b)
        };
        let area = open_area(&cave, DVec3::ZERO, [u, v], 12.0);
        let disc = std::f64::consts::PI * 4.0;
        assert!((area / disc - 1.0).abs() < 0.05, "{area} vs {disc}");
        // The signs decided by the bound are those of every point's own value.
        let cell = 12.0 / CELLS as f64;
        let at = |i: usize, j: usize| ((i as f64 + 0.5) * cell - 6.0, (j as f64 + 0.5) * cell - 6.0);
        let value = |i: usize, j: usize| cave(DVec3::new(0.0, at(i, j).0, at(i, j).1));
        let every: Vec<bool> = (0..CELLS * CELLS).map(|k| value(k % CELLS, k / CELLS) < 0.0).collect();
        assert_eq!(signs(&value, cell), every);
    }
}
