//! Where water cannot leave a hollow: it fills it up to its spill point. The whole footprint
//! is filled once by a priority flood from its edge (Barnes et al. 2014): cells are taken
//! lowest first, each raised to at least the level of the cell the flood reached it from, and
//! each remembers that cell, the way its water leaves the domain. Along that way the filled
//! level never rises, so water following it never climbs and never comes back.
//!
//! A hollow is the connected set of cells at one filled level that the filling raised: its
//! pool. Its outlet is the first cell lower than its level on the way out (or a cell on the
//! footprint's edge: the water leaves the domain there); the cells from a start to the
//! outlet are the route across it, used where the pool is too shallow to count (a flat) or
//! where the water must cross it without filling it.

use std::cmp::Ordering;
use std::collections::{BinaryHeap, VecDeque};

use crate::ground::Grid;

/// The footprint filled to its spill points.
#[derive(Debug, Clone, PartialEq)]
pub struct Filled {
    /// Filled level of each cell: its height, or the surface of the hollow it lies in.
    pub level: Vec<f64>,
    /// The neighbour the flood reached each cell from (towards the edge); none on the edge.
    toward: Vec<Option<usize>>,
}

/// The hollow holding a cell.
#[derive(Debug, Clone, PartialEq)]
pub struct Hollow {
    /// Water surface elevation, metres.
    pub level: f64,
    /// Cells below the level, breadth first from the start.
    pub flooded: Vec<usize>,
    /// Where the water leaves: lower than the level, or on the footprint's edge.
    pub outlet: usize,
    /// Cells from the start to the outlet (both included).
    pub route: Vec<usize>,
}

#[derive(PartialEq)]
struct Entry {
    level: f64,
    seq: u64,
    cell: usize,
}

impl Eq for Entry {}

impl Ord for Entry {
    fn cmp(&self, other: &Self) -> Ordering {
        other.level.total_cmp(&self.level).then(other.seq.cmp(&self.seq))
    }
}

impl PartialOrd for Entry {
    fn partial_cmp(&self, other: &Self) -> Option<Ordering> {
        Some(self.cmp(other))
    }
}

/// Fills every hollow of `grid` to its spill point.
pub fn fill(grid: &Grid) -> Filled {
    let n = grid.heights.len();
    let mut level = grid.heights.clone();
    let mut toward = vec![None; n];
    let mut queued = vec![false; n];
    let mut heap = BinaryHeap::new();
    let mut seq = 0;
    for cell in (0..n).filter(|&c| grid.on_edge(c)) {
        queued[cell] = true;
        seq += 1;
        heap.push(Entry { level: level[cell], seq, cell });
    }
    while let Some(Entry { cell, .. }) = heap.pop() {
        for (next, _) in grid.neighbours(cell) {
            if !queued[next] {
                queued[next] = true;
                level[next] = level[next].max(level[cell]);
                toward[next] = Some(cell);
                seq += 1;
                heap.push(Entry { level: level[next], seq, cell: next });
            }
        }
    }
    Filled { level, toward }
}

impl Filled {
    /// The way out from `start`: the cells to the first one lower than `start`'s level, or to
    /// the footprint's edge.
    pub fn route(&self, start: usize) -> Vec<usize> {
        let mut route = vec![start];
        let mut cell = start;
        while let Some(next) = self.toward[cell] {
            route.push(next);
            cell = next;
            if self.level[next] < self.level[start] {
                break;
            }
        }
        route
    }

    /// The hollow holding `start` (nothing flooded on a slope or a flat).
    pub fn hollow(&self, grid: &Grid, start: usize) -> Hollow {
        let level = self.level[start];
        let route = self.route(start);
        let mut seen = vec![false; grid.heights.len()];
        let mut queue = VecDeque::from([start]);
        seen[start] = true;
        let mut flooded = Vec::new();
        while let Some(cell) = queue.pop_front() {
            if grid.heights[cell] < level {
                flooded.push(cell);
            }
            for (next, _) in grid.neighbours(cell) {
                if !seen[next] && self.level[next] == level {
                    seen[next] = true;
                    queue.push_back(next);
                }
            }
        }
        let outlet = route.last().copied().unwrap_or(start);
        Hollow { level, flooded, outlet, route }
    }
}

#[cfg(test)]
mod tests {
    use glam::DVec2;

    use super::*;

    fn grid(heights: &[f64], nx: usize) -> Grid {
        Grid { cell: 1.0, nx, ny: heights.len() / nx, origin: DVec2::ZERO, heights: heights.to_vec() }
    }

    #[test]
    fn a_hollow_fills_to_its_lowest_rim_and_spills_there() {
        #[rustfmt::skip]
        let g = grid(&[
            9.0, 9.0, 9.0, 9.0, 9.0,
            9.0, 5.0, 4.0, 6.0, 9.0,
            9.0, 5.0, 3.0, 7.0, 9.0,
            9.0, 9.0, 8.0, 9.0, 9.0,
            9.0, 9.0, 2.0, 9.0, 9.0,
        ], 5);
        let f = fill(&g).hollow(&g, 12);
        // The flood comes from the 2 on the south edge over the 8 south of the hollow, the
        // hollow's lowest rim: the level is 8 and the water spills south.
        assert_eq!(f.level, 8.0);
        assert_eq!(f.outlet, 22);
        assert_eq!(f.route.first(), Some(&12));
        assert_eq!(f.route.last(), Some(&22));
        let mut flooded = f.flooded.clone();
        flooded.sort();
        assert_eq!(flooded, vec![6, 7, 8, 11, 12, 13]);
        // From the rim the way out leaves the hollow at once.
        assert_eq!(fill(&g).route(17), vec![17, 22]);
    }

    #[test]
    fn a_flat_drains_to_the_edge_with_nothing_flooded() {
        let g = grid(&[1.0; 25], 5);
        let f = fill(&g).hollow(&g, 12);
        assert!(f.flooded.is_empty());
        assert!(g.on_edge(f.outlet));
        assert!(f.route.len() >= 2 && f.route[0] == 12);
    }
}
