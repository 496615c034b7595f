//! Cross-section images of the model: a horizontal slice at height z, or a vertical one at
//! y = const (which cuts conduits across and shows their section shapes). The PNG shows rock
//! (grey, darker with depth into the rock), cave air (black), water (blue) and air above the
//! ground (white), with the karst outline; the EXR stores the raw fields (R: f, G: cave,
//! B: water) for other tools.

use std::path::Path;

use glam::DVec3;
use karst_raster::{Canvas, Rgb};

use crate::CarvedTerrain;

/// Which plane to cut.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Plane {
    /// Horizontal, at this height.
    Z(f64),
    /// Vertical, at this northing.
    Y(f64),
}

/// A grid of points over the domain in `plane`, `pixel` metres apart: (width, height, point).
pub struct Grid {
    pub width: usize,
    pub height: usize,
    lo: DVec3,
    hi: DVec3,
    plane: Plane,
    pixel: f64,
}

impl Grid {
    pub fn new(field: &CarvedTerrain, plane: Plane, pixel: f64) -> Self {
        let d = &field.model().domain;
        let (lo, hi) = (DVec3::from_array(d.min), DVec3::from_array(d.max));
        let (u, v) = match plane {
            Plane::Z(_) => (hi.x - lo.x, hi.y - lo.y),
            Plane::Y(_) => (hi.x - lo.x, hi.z - lo.z),
        };
        let size = |s: f64| ((s / pixel).ceil() as usize).clamp(1, 8192);
        Grid { width: size(u), height: size(v), lo, hi, plane, pixel }
    }

    /// The point of pixel (x, y), y down (north, or up, at the top).
    pub fn point(&self, x: usize, y: usize) -> DVec3 {
        let u = self.lo.x + (x as f64 + 0.5) * self.pixel;
        match self.plane {
            Plane::Z(z) => DVec3::new(u, self.hi.y - (y as f64 + 0.5) * self.pixel, z),
            Plane::Y(n) => DVec3::new(u, n, self.hi.z - (y as f64 + 0.5) * self.pixel),
        }
    }
}

/// The colour of one point.
fn colour(field: &CarvedTerrain, p: DVec3, pixel: f64) -> Rgb {
    let f = field.eval(p);
    if f < 0.0 {
        let cave = field.cave(p);
        if cave.abs() < pixel * 0.7 {
            return [150, 60, 20];
        }
        let shade = (170.0 - (-f).min(40.0) * 2.0) as u8;
        return [shade, shade, shade.saturating_sub(10)];
    }
    if field.water(p) < 0.0 {
        return [40, 90, 220];
    }
    if field.cave(p) < 0.0 { [10, 10, 10] } else { [250, 250, 250] }
}

/// Writes the PNG slice.
pub fn write_png(field: &CarvedTerrain, plane: Plane, pixel: f64, path: &Path) -> std::io::Result<()> {
    let grid = Grid::new(field, plane, pixel);
    let mut canvas = Canvas::new(grid.width as u32, grid.height as u32, [255, 255, 255]);
    for y in 0..grid.height {
        for x in 0..grid.width {
            canvas.set(x as i64, y as i64, colour(field, grid.point(x, y), pixel));
        }
    }
    let label = match plane {
        Plane::Z(z) => format!("z = {z} m"),
        Plane::Y(n) => format!("y = {n} m"),
    };
    canvas.text((4, 4), &label, 1, [200, 0, 0]);
    canvas.write_png(path)
}

/// Writes the EXR slice: R = f, G = cave, B = water.
pub fn write_exr(
    field: &CarvedTerrain,
    plane: Plane,
    pixel: f64,
    path: &Path,
) -> Result<(), exr::error::Error> {
    let grid = Grid::new(field, plane, pixel);
    exr::prelude::write_rgb_file(path, grid.width, grid.height, |x, y| {
        let p = grid.point(x, y);
        (field.eval(p) as f32, field.cave(p) as f32, field.water(p) as f32)
    })
}
