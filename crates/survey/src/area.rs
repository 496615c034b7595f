//! The area of a station's open region: the cells of a square lattice in the station's plane,
//! centred on the measured point, flooded from it through open cells (4-connected), so that
//! another passage crossing the plane nearby does not count.

use glam::DVec3;

/// Cells along each side of the lattice.
const CELLS: usize = 40;

/// Area, m², of the open region of the plane spanned by the unit vectors `u`, `v` that holds
/// `centre`, within a square of side `side` centred on it; `cave` is negative inside.
pub fn open_area(cave: &impl Fn(DVec3) -> f64, centre: DVec3, [u, v]: [DVec3; 2], side: f64) -> f64 {
    let cell = side / CELLS as f64;
    let at = |i: usize, j: usize| {
        let x = (i as f64 + 0.5) * cell - side / 2.0;
        let y = (j as f64 + 0.5) * cell - side / 2.0;
        centre + u * x + v * y
    };
    let open: Vec<bool> = (0..CELLS * CELLS).map(|k| cave(at(k % CELLS, k / CELLS)) < 0.0).collect();
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
    }
}
