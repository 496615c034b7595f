//! Catchment recharge: the area of terrain draining to each sink, by D8 flow accumulation.
//!
//! The terrain is sampled at the centres of a grid of `hydro.catchment_cell` cells over the
//! domain's footprint. Cells are visited from the highest to the lowest; each passes its area
//! (its own plus what it received) to the lowest of its eight neighbours when that one is lower,
//! the drop measured per metre of distance (O'Callaghan & Mark 1984). A sink swallows all that
//! reaches its cell, so a sink downhill of another only gets what the first one let through.
//! Cells with no lower neighbour (flats, closed hollows) keep their water: a sink on a flat
//! terrain drains its own cell only.

use crate::view::HydroView;
use karst_scene::budget::{Cheaper, Estimate, OverBudget};
use karst_scene::keypoint::KeyPointKind;
use karst_scene::keypoints_of;

/// Bytes per cell of the D8 grid: its height, its area and its place in the order of heights.
const BYTES_PER_CELL: f64 = 32.0;

/// Refuses a catchment grid that would not fit in the memory budget.
pub fn check(view: &HydroView) -> Result<(), OverBudget> {
    let size = view.domain.size();
    let cells = |cell: f64| (size.x / cell).ceil().max(1.0) * (size.y / cell).ceil().max(1.0);
    let cell = view.hydro.catchment_cell;
    let estimate = Estimate {
        what: format!("{:.2e} catchment cells", cells(cell)),
        bytes: cells(cell) * BYTES_PER_CELL,
        field: "hydro.catchment_cell".into(),
        value: cell,
    };
    view.budget.check(estimate, Cheaper::Larger, false, |c| cells(c) * BYTES_PER_CELL)
}

/// Catchment area of each sink of `scene`, m², by name, in key point order.
pub fn catchments(view: &HydroView) -> Vec<(String, f64)> {
    let grid = Grid::of(view);
    let sinks: Vec<(String, usize)> = keypoints_of(view.keypoints, KeyPointKind::Sink)
        .map(|(_, k)| (k.name.clone(), grid.cell_of(k.position[0], k.position[1])))
        .collect();
    let mut area = vec![grid.cell * grid.cell; grid.heights.len()];
    let mut captured = vec![0.0; sinks.len()];
    for c in grid.highest_first() {
        let at_sink: Vec<usize> = (0..sinks.len()).filter(|&s| sinks[s].1 == c).collect();
        if !at_sink.is_empty() {
            for &s in &at_sink {
                captured[s] += area[c] / at_sink.len() as f64;
            }
        } else if let Some(next) = grid.steepest_descent(c) {
            area[next] += area[c];
        }
    }
    sinks.into_iter().zip(captured).map(|((name, _), a)| (name, a)).collect()
}

/// Terrain heights at cell centres.
struct Grid {
    cell: f64,
    nx: usize,
    ny: usize,
    origin: [f64; 2],
    heights: Vec<f64>,
}

impl Grid {
    fn of(view: &HydroView) -> Grid {
        let d = view.domain;
        let cell = view.hydro.catchment_cell;
        let nx = (((d.max[0] - d.min[0]) / cell).ceil() as usize).max(1);
        let ny = (((d.max[1] - d.min[1]) / cell).ceil() as usize).max(1);
        let origin = [d.min[0], d.min[1]];
        let heights = (0..nx * ny)
            .map(|i| {
                let (x, y) = ((i % nx) as f64 + 0.5, (i / nx) as f64 + 0.5);
                view.terrain.height(origin[0] + x * cell, origin[1] + y * cell)
            })
            .collect();
        Grid { cell, nx, ny, origin, heights }
    }

    fn cell_of(&self, x: f64, y: f64) -> usize {
        let i = (((x - self.origin[0]) / self.cell).floor().max(0.0) as usize).min(self.nx - 1);
        let j = (((y - self.origin[1]) / self.cell).floor().max(0.0) as usize).min(self.ny - 1);
        j * self.nx + i
    }

    /// Cells from the highest to the lowest, ties by index.
    fn highest_first(&self) -> Vec<usize> {
        let mut order: Vec<usize> = (0..self.heights.len()).collect();
        order.sort_by(|&a, &b| self.heights[b].total_cmp(&self.heights[a]).then(a.cmp(&b)));
        order
    }

    /// The neighbour with the steepest drop from `c`, if any is lower.
    fn steepest_descent(&self, c: usize) -> Option<usize> {
        let (i, j) = ((c % self.nx) as i64, (c / self.nx) as i64);
        let mut best = None;
        let mut best_drop = 0.0;
        for (di, dj) in [(-1, -1), (0, -1), (1, -1), (-1, 0), (1, 0), (-1, 1), (0, 1), (1, 1)] {
            let (a, b) = (i + di, j + dj);
            if a < 0 || b < 0 || a >= self.nx as i64 || b >= self.ny as i64 {
                continue;
            }
            let n = b as usize * self.nx + a as usize;
            let drop = (self.heights[c] - self.heights[n]) / ((di * di + dj * dj) as f64).sqrt();
            if drop > best_drop {
                best_drop = drop;
                best = Some(n);
            }
        }
        best
    }
}

#[cfg(test)]
mod tests {
    use std::path::Path;

    use karst_scene::{Scene, SceneView};

    use super::*;

    fn scene(gradient: &str, sinks: &[(&str, f64, f64)]) -> Scene {
        let mut text = format!(
            "name = \"t\"\nseed = 1\n[domain]\nmin = [0, 0, 0]\nmax = [100, 50, 50]\n\
             [terrain]\nkind = \"plane\"\nelevation = 40\ngradient = {gradient}\n\
             [[geology.water_tables]]\nname = \"wt\"\nelevation = 5\n\
             [[keypoints]]\nname = \"s\"\nkind = \"spring\"\nposition = [99, 25, 5]\nwater_table = \"wt\"\n"
        );
        for (name, x, y) in sinks {
            text += &format!("[[keypoints]]\nname = \"{name}\"\nkind = \"sink\"\nposition = [{x}, {y}, 1]\n");
        }
        Scene::parse(&text, Path::new("t.toml")).unwrap()
    }

    #[test]
    fn a_sink_on_an_east_slope_drains_its_row_uphill() {
        // 10 m cells, terrain falling east: the sink in column 5 gets columns 0..=5 of its row.
        let c = catchments(&HydroView::of(&scene("[-0.1, 0.0]", &[("a", 55.0, 25.0)])));
        assert_eq!(c, vec![("a".to_string(), 600.0)]);
    }

    #[test]
    fn an_upstream_sink_swallows_what_would_reach_a_downstream_one() {
        let c =
            catchments(&HydroView::of(&scene("[-0.1, 0.0]", &[("up", 25.0, 25.0), ("down", 75.0, 25.0)])));
        assert_eq!(c, vec![("up".to_string(), 300.0), ("down".to_string(), 500.0)]);
    }

    #[test]
    fn a_flat_terrain_gives_each_sink_its_own_cell() {
        let c = catchments(&HydroView::of(&scene("[0.0, 0.0]", &[("a", 55.0, 25.0)])));
        assert_eq!(c, vec![("a".to_string(), 100.0)]);
    }
}
