//! Cross-section images of the model: a horizontal slice at height z, or a vertical one at
//! y or x = const (which cuts conduits across and shows their section shapes). The PNG shows rock
//! (grey, darker with depth into the rock), cave air (black), water (blue) and air above the
//! ground (white), with the karst outline (brown); the EXR stores the raw fields (R: f, G: cave,
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
    /// Vertical, at this northing (x across the image).
    Y(f64),
    /// Vertical, at this easting (y across the image).
    X(f64),
}

/// A grid of points over the domain (or a window of it) in `plane`, `pixel` metres apart.
pub struct SliceGrid {
    pub width: usize,
    pub height: usize,
    /// In-plane ranges: (u0, v1) is the top-left corner.
    u0: f64,
    v1: f64,
    plane: Plane,
    pixel: f64,
}

impl SliceGrid {
    /// `window` = [u0, u1, v0, v1] in the plane's coordinates (x, y for z slices; x, z for y
    /// slices; y, z for x slices); the domain's extent when `None`.
    pub fn new(field: &CarvedTerrain, plane: Plane, pixel: f64, window: Option<[f64; 4]>) -> Self {
        let d = &field.model().domain;
        let [u0, u1, v0, v1] = window.unwrap_or(match plane {
            Plane::Z(_) => [d.min[0], d.max[0], d.min[1], d.max[1]],
            Plane::Y(_) => [d.min[0], d.max[0], d.min[2], d.max[2]],
            Plane::X(_) => [d.min[1], d.max[1], d.min[2], d.max[2]],
        });
        let size = |s: f64| ((s / pixel).ceil().max(1.0) as usize).min(8192);
        SliceGrid { width: size(u1 - u0), height: size(v1 - v0), u0, v1, plane, pixel }
    }

    /// The point of pixel (x, y), y down (north, or up, at the top).
    pub fn point(&self, x: usize, y: usize) -> DVec3 {
        let u = self.u0 + (x as f64 + 0.5) * self.pixel;
        let v = self.v1 - (y as f64 + 0.5) * self.pixel;
        match self.plane {
            Plane::Z(z) => DVec3::new(u, v, z),
            Plane::Y(n) => DVec3::new(u, n, v),
            Plane::X(e) => DVec3::new(e, u, v),
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
pub fn write_png(field: &CarvedTerrain, grid: &SliceGrid, path: &Path) -> std::io::Result<()> {
    let pixel = grid.pixel;
    let mut canvas = Canvas::new(grid.width as u32, grid.height as u32, [255, 255, 255]);
    for y in 0..grid.height {
        for x in 0..grid.width {
            canvas.set(x as i64, y as i64, colour(field, grid.point(x, y), pixel));
        }
    }
    let label = match grid.plane {
        Plane::Z(z) => format!("z = {z} m"),
        Plane::Y(n) => format!("y = {n} m"),
        Plane::X(e) => format!("x = {e} m"),
    };
    canvas.text((4, 4), &label, 1, [200, 0, 0]);
    canvas.write_png(path)
}

/// Writes the EXR slice: R = f, G = cave, B = water.
pub fn write_exr(field: &CarvedTerrain, grid: &SliceGrid, path: &Path) -> Result<(), exr::error::Error> {
    exr::prelude::write_rgb_file(path, grid.width, grid.height, |x, y| {
        let p = grid.point(x, y);
        (field.eval(p) as f32, field.cave(p) as f32, field.water(p) as f32)
    })
}

/// The cross-section library: one filled section per conduit type (radius 1, `ratio`,
/// `asymmetry`), side by side and labelled, `scale` pixels per metre.
pub fn write_sections_png(ratio: f64, asymmetry: f64, scale: f64, path: &Path) -> std::io::Result<()> {
    use crate::section::{Section, Shape};
    use karst_skeleton::ConduitType;

    let cell = (scale * 4.0).ceil() as usize;
    let kinds = ConduitType::ALL;
    let mut canvas = Canvas::new((cell * kinds.len()) as u32, (cell + 16) as u32, [250, 250, 250]);
    let shape = Shape { radius: 1.0, ratio: ratio as f32, asymmetry: asymmetry as f32 };
    for (k, kind) in kinds.into_iter().enumerate() {
        let section = Section::of(kind, shape);
        for y in 0..cell {
            for x in 0..cell {
                let q =
                    glam::DVec2::new(x as f64 + 0.5 - cell as f64 / 2.0, cell as f64 / 2.0 - y as f64 - 0.5)
                        / scale;
                let d = section.distance(q);
                let colour = if d.abs() < 1.0 / scale {
                    [150, 60, 20]
                } else if d < 0.0 {
                    [10, 10, 10]
                } else {
                    [170, 170, 160]
                };
                canvas.set((k * cell + x) as i64, (y + 16) as i64, colour);
            }
        }
        canvas.text(((k * cell) as i64 + 4, 4), kind.name(), 1, [200, 0, 0]);
    }
    canvas.write_png(path)
}
