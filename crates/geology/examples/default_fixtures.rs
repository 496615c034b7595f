//! Writes the data files of the default scene (`fixtures/scenes/data/`): the heightfield of a
//! limestone plateau sloping east into a valley (16-bit PNG, 101 × 101 pixels every 10 m,
//! 1 cm per unit) and a gently dipping inception horizon (GOCAD TSurf, 21 × 21 vertices every
//! 50 m). `cargo run --release -p karst-geology --example default_fixtures`.

use std::path::Path;

use karst_geodata::tin::write_tsurf;
use karst_geology::heightfield::{HeightGrid, write_png};
use karst_geology::tin::Tin;

/// The plateau: 280 m on the west edge falling 12 % to the east, low rolling hills (never below
/// the plain slope, so the scene's key points stay underground) and a shallow valley that
/// opens towards the spring on the east edge.
fn ground(x: f64, y: f64) -> f64 {
    let hills = 3.0 * (1.0 + (x / 95.0).sin() * (y / 120.0).cos());
    let east = ((x - 600.0) / 400.0).clamp(0.0, 1.0);
    let valley = 2.5 * (-((y - 500.0) / 160.0).powi(2)).exp() * east * east;
    280.0 - 0.12 * x + hills * (1.0 - east) - valley + 2.5 * east * east
}

/// The horizon: 215 m on the west edge dipping 2° east, with a 3 m gentle fold along y.
fn horizon(x: f64, y: f64) -> f64 {
    215.0 - 2f64.to_radians().tan() * x + 3.0 * (y / 170.0).sin()
}

fn main() -> std::io::Result<()> {
    let folder = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../fixtures/scenes/data");
    std::fs::create_dir_all(&folder)?;
    let heights =
        (0..101).flat_map(|j| (0..101).map(move |i| ground(10.0 * i as f64, 10.0 * j as f64))).collect();
    write_png(&folder.join("plateau.png"), &HeightGrid::new([0.0, 0.0], 10.0, 101, 101, heights), 0.0, 0.01)?;
    let n = 21u32;
    let vertices = (0..n)
        .flat_map(|j| (0..n).map(move |i| (50.0 * i as f64, 50.0 * j as f64)))
        .map(|(x, y)| [x, y, (horizon(x, y) * 1000.0).round() / 1000.0])
        .collect();
    let mut triangles = Vec::new();
    for j in 0..n - 1 {
        for i in 0..n - 1 {
            let a = j * n + i;
            triangles.push([a, a + 1, a + n + 1]);
            triangles.push([a, a + n + 1, a + n]);
        }
    }
    let tin = Tin::new(vertices, triangles, "horizon").map_err(std::io::Error::other)?;
    write_tsurf(&folder.join("marl-parting.ts"), "marl-parting", &tin.vertices, &tin.triangles)
}
