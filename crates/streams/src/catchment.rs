//! The surface catchment of the streams: rain that runs off the terrain into them.
//!
//! Every grid cell a stream or a pool covers is captured by it (the first node, in node order,
//! lying in the cell; a pool by its flooded or dug cells). Cells are visited from the highest
//! to the lowest; an uncaptured cell passes its area (its own plus what it received) to its
//! D8 receiver, a captured cell gives it to its node (O'Callaghan & Mark 1984, as the hydro
//! stage's sink recharge). What drains out of the domain or into a hollow no stream reaches is
//! not part of the network. The lateral inflow of a node is its area times the runoff.

use crate::ground::Grid;
use crate::network::Network;

/// Seconds in a year (365.25 days).
const YEAR: f64 = 365.25 * 86_400.0;

/// Lateral inflow of each node of `net`, m³/s, for `runoff` mm per year.
pub fn lateral(grid: &Grid, net: &Network, runoff: f64) -> Vec<f64> {
    let mut captor: Vec<Option<u32>> = vec![None; grid.heights.len()];
    let mut cells: Vec<(&usize, &usize)> = net.pool_cells.iter().collect();
    cells.sort_unstable();
    for (&cell, &pool) in cells {
        captor[cell] = Some(net.pools[pool].node);
    }
    for (n, p) in net.positions.iter().enumerate() {
        let inside = p.x >= grid.origin.x
            && p.y >= grid.origin.y
            && p.x <= grid.origin.x + grid.nx as f64 * grid.cell
            && p.y <= grid.origin.y + grid.ny as f64 * grid.cell;
        let c = grid.cell_of(p.truncate());
        if inside && captor[c].is_none() {
            captor[c] = Some(n as u32);
        }
    }
    let rate = runoff / 1000.0 / YEAR;
    let mut area = vec![grid.area(); grid.heights.len()];
    let mut inflow = vec![0.0; net.positions.len()];
    for c in grid.highest_first() {
        match captor[c] {
            Some(n) => inflow[n as usize] += area[c] * rate,
            None => {
                if let Some(next) = grid.receiver(c) {
                    area[next] += area[c];
                }
            }
        }
    }
    inflow
}
