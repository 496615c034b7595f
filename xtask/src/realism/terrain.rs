//! The population's terrains, as heightfields: fractal noise, a plateau ending in a cliff above a
//! lowland, and a valley cut into a plateau. Each is scaled to the scene's relief and written as
//! the 16-bit PNG a user would bring (`[terrain] kind = "heightfield"`).

use karst_geology::heightfield::HeightGrid;
use karst_scene::rng::Random;

/// The kinds of terrain the population draws from, in equal shares.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Relief {
    /// Hills and closed depressions: fractal value noise (five octaves).
    Noise,
    /// A high plateau ending in a cliff above a lowland, both rough.
    PlateauAndCliff,
    /// A plateau cut by a winding valley whose floor falls along its course.
    Valley,
}

impl Relief {
    pub const ALL: [Relief; 3] = [Relief::Noise, Relief::PlateauAndCliff, Relief::Valley];

    pub fn name(self) -> &'static str {
        match self {
            Relief::Noise => "noise",
            Relief::PlateauAndCliff => "plateau-and-cliff",
            Relief::Valley => "valley",
        }
    }
}

/// Pixels along each side of every heightfield.
pub const PIXELS: u32 = 129;
/// Metres per pixel unit of the written PNG: heights are stored to 2.5 cm, up to 1,638 m above the lowest.
pub const VERTICAL_SCALE: f64 = 0.025;

/// A terrain of `relief` over a square of [`PIXELS`] pixels `cell` metres apart whose lowest point
/// is at `base` and highest at `base + height`, heights rounded to what the PNG stores.
pub fn heightfield(relief: Relief, cell: f64, base: f64, height: f64, rng: &mut Random) -> HeightGrid {
    let n = PIXELS as usize;
    let noise = Noise::new(rng);
    let course = rng.range(0.0, std::f64::consts::TAU);
    let shape: Vec<f64> = (0..n * n)
        .map(|i| {
            let (u, v) = ((i % n) as f64 / (n - 1) as f64, (i / n) as f64 / (n - 1) as f64);
            match relief {
                Relief::Noise => noise.at(u, v),
                Relief::PlateauAndCliff => plateau_and_cliff(u, v, course, &noise),
                Relief::Valley => valley(u, v, course, &noise),
            }
        })
        .collect();
    let (lo, hi) = shape.iter().fold((f64::MAX, f64::MIN), |(lo, hi), &h| (lo.min(h), hi.max(h)));
    let heights = shape
        .iter()
        .map(|h| {
            let z = height * (h - lo) / (hi - lo).max(1e-12);
            base + (z / VERTICAL_SCALE).round() * VERTICAL_SCALE
        })
        .collect();
    HeightGrid::new([0.0, 0.0], cell, PIXELS, PIXELS, heights)
}

/// A plateau on one side of a line across the square (direction `course`), a cliff a tenth of
/// the side wide, a lowland a third as rough below.
fn plateau_and_cliff(u: f64, v: f64, course: f64, noise: &Noise) -> f64 {
    let across = (u - 0.5) * course.cos() + (v - 0.5) * course.sin();
    let step = 0.5 * (1.0 + ((across - 0.1) / 0.05).tanh());
    step + 0.25 * noise.at(u, v) * (0.3 + 0.7 * step)
}

/// A valley through the centre along `course`, winding, its floor falling along its course,
/// its sides rising to a plateau.
fn valley(u: f64, v: f64, course: f64, noise: &Noise) -> f64 {
    let (c, s) = (course.cos(), course.sin());
    let (x, y) = (u - 0.5, v - 0.5);
    let along = x * c + y * s;
    let across = -x * s + y * c - 0.08 * (along * 9.0).sin();
    let side = (across.abs() / 0.25).min(1.0);
    0.7 * side.powf(1.5) + 0.15 * (along + 0.7) + 0.25 * noise.at(u, v)
}

/// Fractal value noise on the unit square: five octaves of bilinear random lattices.
struct Noise {
    lattices: Vec<(usize, Vec<f64>)>,
}

impl Noise {
    fn new(rng: &mut Random) -> Noise {
        let lattices = (0..5)
            .map(|octave| {
                let cells = 2usize << octave;
                (cells, (0..(cells + 1) * (cells + 1)).map(|_| rng.uniform()).collect())
            })
            .collect();
        Noise { lattices }
    }

    fn at(&self, u: f64, v: f64) -> f64 {
        let mut sum = 0.0;
        let mut amplitude = 1.0;
        for (cells, values) in &self.lattices {
            let (x, y) = (u * *cells as f64, v * *cells as f64);
            let (i, j) = ((x as usize).min(cells - 1), (y as usize).min(cells - 1));
            let (fx, fy) = (smooth(x - i as f64), smooth(y - j as f64));
            let at = |a: usize, b: usize| values[b * (cells + 1) + a];
            let bottom = at(i, j) + (at(i + 1, j) - at(i, j)) * fx;
            let top = at(i, j + 1) + (at(i + 1, j + 1) - at(i, j + 1)) * fx;
            sum += amplitude * (bottom + (top - bottom) * fy);
            amplitude *= 0.5;
        }
        sum
    }
}

fn smooth(t: f64) -> f64 {
    t * t * (3.0 - 2.0 * t)
}
