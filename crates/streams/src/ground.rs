//! The terrain as the water sees it: heights and slopes anywhere (the scene's terrain,
//! sampled), and a grid of cell-centre heights over the domain's footprint for the catchment
//! and the pools' flood fill.

use glam::{DVec2, DVec3};

use karst_geology::{Domain, Terrain};

/// The scene's terrain within the domain.
pub struct Ground<'a> {
    pub terrain: &'a Terrain,
    pub domain: Domain,
    /// Half the distance of the central differences of the gradient, metres.
    pub probe: f64,
}

impl Ground<'_> {
    pub fn height(&self, p: DVec2) -> f64 {
        self.terrain.height(p.x, p.y)
    }

    /// Gradient of the height by central differences.
    pub fn gradient(&self, p: DVec2) -> DVec2 {
        let h = self.probe;
        let dx = self.height(p + DVec2::X * h) - self.height(p - DVec2::X * h);
        let dy = self.height(p + DVec2::Y * h) - self.height(p - DVec2::Y * h);
        DVec2::new(dx, dy) / (2.0 * h)
    }

    /// True when (x, y) lies over the domain's footprint.
    pub fn inside(&self, p: DVec2) -> bool {
        let (lo, hi) = (self.domain.min, self.domain.max);
        p.x >= lo[0] && p.x <= hi[0] && p.y >= lo[1] && p.y <= hi[1]
    }

    /// The point where the segment from `a` (inside) towards `b` leaves the footprint.
    pub fn edge_point(&self, a: DVec2, b: DVec2) -> DVec2 {
        let (lo, hi) = (self.domain.min, self.domain.max);
        let d = b - a;
        let mut t: f64 = 1.0;
        for (axis, (l, h)) in [(0, (lo[0], hi[0])), (1, (lo[1], hi[1]))] {
            let (p, v) = (a[axis], d[axis]);
            if v > 0.0 && p + v > h {
                t = t.min((h - p) / v);
            } else if v < 0.0 && p + v < l {
                t = t.min((l - p) / v);
            }
        }
        a + d * t.max(0.0)
    }

    /// `p` on the ground.
    pub fn on_ground(&self, p: DVec2) -> DVec3 {
        p.extend(self.height(p))
    }
}

/// Terrain heights at the centres of square cells over the domain's footprint.
pub struct Grid {
    pub cell: f64,
    pub nx: usize,
    pub ny: usize,
    pub origin: DVec2,
    pub heights: Vec<f64>,
}

/// The eight neighbours, as (di, dj).
pub const NEIGHBOURS: [(i64, i64); 8] =
    [(-1, -1), (0, -1), (1, -1), (-1, 0), (1, 0), (-1, 1), (0, 1), (1, 1)];

impl Grid {
    pub fn of(ground: &Ground, cell: f64) -> Grid {
        let d = &ground.domain;
        let nx = (((d.max[0] - d.min[0]) / cell).ceil() as usize).max(1);
        let ny = (((d.max[1] - d.min[1]) / cell).ceil() as usize).max(1);
        let origin = DVec2::new(d.min[0], d.min[1]);
        let mut grid = Grid { cell, nx, ny, origin, heights: Vec::new() };
        grid.heights = (0..nx * ny).map(|c| ground.height(grid.centre(c))).collect();
        grid
    }

    pub fn centre(&self, c: usize) -> DVec2 {
        self.origin + DVec2::new((c % self.nx) as f64 + 0.5, (c / self.nx) as f64 + 0.5) * self.cell
    }

    pub fn cell_of(&self, p: DVec2) -> usize {
        let q = (p - self.origin) / self.cell;
        let i = (q.x.floor().max(0.0) as usize).min(self.nx - 1);
        let j = (q.y.floor().max(0.0) as usize).min(self.ny - 1);
        j * self.nx + i
    }

    /// The neighbours of `c` inside the grid, with the distance to each in cells.
    pub fn neighbours(&self, c: usize) -> impl Iterator<Item = (usize, f64)> + '_ {
        let (i, j) = ((c % self.nx) as i64, (c / self.nx) as i64);
        NEIGHBOURS.iter().filter_map(move |&(di, dj)| {
            let (a, b) = (i + di, j + dj);
            let inside = a >= 0 && b >= 0 && a < self.nx as i64 && b < self.ny as i64;
            inside.then(|| (b as usize * self.nx + a as usize, ((di * di + dj * dj) as f64).sqrt()))
        })
    }

    /// True for the cells along the footprint's edge: water there can leave the domain.
    pub fn on_edge(&self, c: usize) -> bool {
        let (i, j) = (c % self.nx, c / self.nx);
        i == 0 || j == 0 || i + 1 == self.nx || j + 1 == self.ny
    }

    /// The D8 receiver of `c`: its neighbour of steepest drop, when one is lower.
    pub fn receiver(&self, c: usize) -> Option<usize> {
        let mut best = (0.0, None);
        for (n, distance) in self.neighbours(c) {
            let drop = (self.heights[c] - self.heights[n]) / distance;
            if drop > best.0 {
                best = (drop, Some(n));
            }
        }
        best.1
    }

    /// Cells from the highest to the lowest, ties by index.
    pub fn highest_first(&self) -> Vec<usize> {
        let mut order: Vec<usize> = (0..self.heights.len()).collect();
        order.sort_by(|&a, &b| self.heights[b].total_cmp(&self.heights[a]).then(a.cmp(&b)));
        order
    }

    pub fn area(&self) -> f64 {
        self.cell * self.cell
    }
}
