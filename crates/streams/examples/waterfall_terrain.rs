//! Writes the heightfield of the `waterfall` preset (`fixtures/scenes/data/waterfall.png`): a
//! valley running east whose north wall climbs in three cliffs with benches between them, in
//! the spirit of Emilien et al. 2015's Figure 1. 241 × 161 pixels every metre, 1 cm per unit.
//! `cargo run --release -p karst-streams --example waterfall_terrain`.

use std::path::Path;

use karst_geology::heightfield::{HeightGrid, write_png};

/// Cliff slope (rise over run): 80.5°, steep enough that water at the lip leaves the rock.
const CLIFF: f64 = 6.0;
/// Benches tilt towards the valley (17°): the water reaches the next lip at about 3 m/s.
const BENCH: f64 = 0.3;

/// The elevation of the north wall and valley at (x, y).
fn ground(x: f64, y: f64) -> f64 {
    let floor = 24.0 - 0.05 * x + 0.05 * (y - 57.0).abs();
    if y < 40.0 {
        return floor + 0.4 * (40.0 - y);
    }
    if y < 75.0 {
        return floor;
    }
    let toe = 24.0 - 0.05 * x + 0.05 * 18.0;
    // The cascade slope (26.6°) from the valley floor up to the lowest bench at 34 m.
    let cascade_top = 103.0;
    let slope = (34.0 - toe) / (cascade_top - 75.0);
    if y < cascade_top {
        return toe + slope * (y - 75.0);
    }
    // Three benches, each 10 m deep, and three cliffs of 24 m, each 4 m wide.
    let mut base = 34.0;
    let mut start = cascade_top;
    for _ in 0..3 {
        let bench_end = start + 10.0;
        if y < bench_end {
            return base + BENCH * (y - start);
        }
        let top = base + BENCH * 10.0;
        let cliff_end = bench_end + 24.0 / CLIFF;
        if y < cliff_end {
            return top + CLIFF * (y - bench_end);
        }
        base = top + 24.0;
        start = cliff_end;
    }
    base + 0.02 * (y - start)
}

fn main() -> std::io::Result<()> {
    let folder = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../fixtures/scenes/data");
    std::fs::create_dir_all(&folder)?;
    let (nx, ny) = (241, 161);
    let heights = (0..ny).flat_map(|j| (0..nx).map(move |i| ground(i as f64, j as f64))).collect();
    write_png(&folder.join("waterfall.png"), &HeightGrid::new([0.0, 0.0], 1.0, nx, ny, heights), 0.0, 0.01)
}
