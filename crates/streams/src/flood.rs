//! Where water cannot leave a hollow: it fills it up to its spill point (a priority flood,
//! Barnes et al. 2014, from the hollow's lowest cell).
//!
//! Cells are taken lowest first from the hollow's rim; the level rises to each taken cell's
//! height. The first taken cell lower than the level is the outlet: water spills into it and
//! runs on downhill from there. A cell on the footprint's edge is an outlet too (the water
//! leaves the domain there). The cells below the final level are the pool; the chain of cells
//! the flood took from the hollow to the outlet is the route across it, used where the pool is
//! too shallow to count (a flat).

use std::cmp::Ordering;
use std::collections::BinaryHeap;

use crate::ground::Grid;

/// A filled hollow.
#[derive(Debug, Clone, PartialEq)]
pub struct Filled {
    /// Water surface elevation, metres.
    pub level: f64,
    /// Cells below the level, in the order the flood took them.
    pub flooded: Vec<usize>,
    /// Where the water leaves: lower than the level, or on the footprint's edge.
    pub outlet: usize,
    /// Cells from the start to the outlet (both included), as the flood reached them.
    pub route: Vec<usize>,
}

#[derive(PartialEq)]
struct Entry {
    height: f64,
    seq: u64,
    cell: usize,
}

impl Eq for Entry {}

impl Ord for Entry {
    fn cmp(&self, other: &Self) -> Ordering {
        other.height.total_cmp(&self.height).then(other.seq.cmp(&self.seq))
    }
}

impl PartialOrd for Entry {
    fn partial_cmp(&self, other: &Self) -> Option<Ordering> {
        Some(self.cmp(other))
    }
}

/// Fills the hollow containing `start`; the flood stops at `max_cells` taken cells (the
/// outlet is then the last cell taken: a lake that large is reported by the caller).
pub fn fill(grid: &Grid, start: usize, max_cells: usize) -> Filled {
    let n = grid.heights.len();
    let mut from = vec![usize::MAX; n];
    let mut taken = vec![false; n];
    let mut heap = BinaryHeap::new();
    let mut seq = 0;
    heap.push(Entry { height: grid.heights[start], seq, cell: start });
    from[start] = start;
    let mut level = grid.heights[start];
    let mut order = Vec::new();
    let outlet = loop {
        let Some(Entry { cell, .. }) = heap.pop() else { break order.last().copied().unwrap_or(start) };
        if taken[cell] {
            continue;
        }
        taken[cell] = true;
        let h = grid.heights[cell];
        if h < level || (grid.on_edge(cell) && cell != start) || order.len() >= max_cells {
            break cell;
        }
        level = level.max(h);
        order.push(cell);
        if grid.on_edge(cell) {
            break cell;
        }
        for (next, _) in grid.neighbours(cell) {
            if !taken[next] && from[next] == usize::MAX {
                from[next] = cell;
                seq += 1;
                heap.push(Entry { height: grid.heights[next], seq, cell: next });
            }
        }
    };
    let mut route = vec![outlet];
    while let Some(&last) = route.last() {
        let previous = from[last];
        if previous == last || previous == usize::MAX {
            break;
        }
        route.push(previous);
    }
    route.reverse();
    let flooded = order.into_iter().filter(|&c| grid.heights[c] < level).collect();
    Filled { level, flooded, outlet, route }
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
        let f = fill(&g, 12, 100);
        // The flood takes 3, 4, 5, 5, 6, 7, then the 8 south of the hollow, whose neighbour 2
        // is lower: the level is 8 and the water spills south.
        assert_eq!(f.level, 8.0);
        assert_eq!(f.outlet, 22);
        assert_eq!(f.route.first(), Some(&12));
        assert_eq!(f.route.last(), Some(&22));
        let mut flooded = f.flooded.clone();
        flooded.sort();
        assert_eq!(flooded, vec![6, 7, 8, 11, 12, 13]);
    }

    #[test]
    fn a_flat_drains_to_the_edge_with_nothing_flooded() {
        let g = grid(&[1.0; 25], 5);
        let f = fill(&g, 12, 100);
        assert!(f.flooded.is_empty());
        assert!(g.on_edge(f.outlet));
        assert!(f.route.len() >= 2 && f.route[0] == 12);
    }
}
