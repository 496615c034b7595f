//! Heightfields: the terrain as a regular grid of elevations read from a 16-bit grayscale PNG
//! or an OpenEXR image (`.exr`, float elevations), interpolated bilinearly. The images' pixels
//! are `karst-geodata`'s ([`karst_geodata::image`]); this module places and scales them.
//!
//! Georeferencing: pixel (column c, row r) of a W × H image stands at
//! x = origin.x + c·cell_size, y = origin.y + (H − 1 − r)·cell_size (row 0 is the north edge, as
//! in every image viewer and GIS export), and its elevation is offset + vertical_scale·value.
//! A pixel equal to `nodata` has no elevation; the heightfield must cover the domain's footprint
//! with valid pixels, since a terrain with holes cannot bound the bedrock.
//!
//! Bilinear interpolation is exact at the pixels and continuous; its Lipschitz bound is the
//! largest, over the grid cells, of |(max |∂h/∂x|, max |∂h/∂y|)|, both maxima taken on the
//! cell's edges (a bilinear patch's partial derivatives are linear between its edges).

use std::path::Path;

use karst_geodata::image::{self, Image, ImageError};
use serde::{Deserialize, Serialize};

pub use karst_geodata::image::MAX_PIXELS;

/// A regular grid of elevations, south row first.
#[derive(Clone, Default, PartialEq, Serialize, Deserialize)]
pub struct HeightGrid {
    /// Position `[x, y]` of the south-west sample.
    pub origin: [f64; 2],
    /// Distance between samples, metres.
    pub cell_size: f64,
    /// Samples along x and y.
    pub nx: u32,
    pub ny: u32,
    /// Elevations, x fastest, south row first (`NaN` where the file had no data).
    pub heights: Vec<f64>,
    /// Lipschitz bound of the bilinear interpolant over its valid cells.
    pub lipschitz: f64,
}

impl std::fmt::Debug for HeightGrid {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "HeightGrid({}×{} at {:?}, cell {} m)", self.nx, self.ny, self.origin, self.cell_size)
    }
}

/// Why a heightfield cannot be read.
#[derive(Debug, thiserror::Error)]
pub enum HeightfieldError {
    #[error("cannot read {file}: {message}")]
    Read { file: String, message: String },
    #[error("{file}: {message}")]
    Content { file: String, message: String },
}

impl HeightfieldError {
    /// The error of the image reader, with the file's name in front.
    fn of(file: &str, error: ImageError) -> HeightfieldError {
        let file = file.to_string();
        match error {
            ImageError::Unreadable(message) => HeightfieldError::Read { file, message },
            ImageError::Content(message) => HeightfieldError::Content { file, message },
        }
    }
}

/// How to turn pixels into elevations and positions.
#[derive(Debug, Clone, Copy)]
pub struct Georeference {
    pub origin: [f64; 2],
    pub cell_size: f64,
    pub vertical_scale: f64,
    pub offset: f64,
    pub nodata: Option<f64>,
}

impl HeightGrid {
    /// Reads a 16-bit (or 8-bit) grayscale PNG.
    pub fn read_png(path: &Path, geo: &Georeference) -> Result<HeightGrid, HeightfieldError> {
        let file = path.display().to_string();
        let bytes = karst_artifact::files::read_regular(path, karst_artifact::files::MAX_DATA_BYTES)
            .map_err(|e| HeightfieldError::Read { file: file.clone(), message: e.to_string() })?;
        HeightGrid::decode_png(&bytes, &file, geo)
    }

    /// Decodes the bytes of a 16-bit (or 8-bit) grayscale PNG named `file` in messages; images
    /// of more than [`MAX_PIXELS`] are refused before their pixels are allocated.
    pub fn decode_png(bytes: &[u8], file: &str, geo: &Georeference) -> Result<HeightGrid, HeightfieldError> {
        let image = image::decode_png(bytes).map_err(|e| HeightfieldError::of(file, e))?;
        Ok(HeightGrid::from_image(&image, geo))
    }

    /// Reads the first layer of an OpenEXR image: its `Y` channel, else `Z`, else `R`, else its
    /// first channel (values as f32, then elevation = offset + vertical_scale·value; a
    /// non-finite value has no elevation).
    pub fn read_exr(path: &Path, geo: &Georeference) -> Result<HeightGrid, HeightfieldError> {
        let file = path.display().to_string();
        let image = image::read_exr(path).map_err(|e| HeightfieldError::of(&file, e))?;
        Ok(HeightGrid::from_image(&image, geo))
    }

    /// The grid of an image's pixels placed by `geo`: rows flipped to south first, elevations
    /// scaled and offset, the no-data value and non-finite values as `NaN`.
    pub fn from_image(image: &Image, geo: &Georeference) -> HeightGrid {
        let (w, h) = (image.width, image.height);
        let mut heights = Vec::with_capacity(w * h);
        for row in image.values.chunks_exact(w.max(1)).rev() {
            heights.extend(row.iter().map(|&v| {
                let missing = !v.is_finite() || geo.nodata == Some(v);
                if missing { f64::NAN } else { geo.offset + geo.vertical_scale * v }
            }));
        }
        HeightGrid::new(geo.origin, geo.cell_size, w as u32, h as u32, heights)
    }

    /// Reads a PNG or, for `.exr` files, an OpenEXR image.
    pub fn read(path: &Path, geo: &Georeference) -> Result<HeightGrid, HeightfieldError> {
        if path.extension().is_some_and(|e| e.eq_ignore_ascii_case("exr")) {
            HeightGrid::read_exr(path, geo)
        } else {
            HeightGrid::read_png(path, geo)
        }
    }

    /// A grid from its samples (x fastest, south row first); computes the Lipschitz bound.
    pub fn new(origin: [f64; 2], cell_size: f64, nx: u32, ny: u32, heights: Vec<f64>) -> HeightGrid {
        let mut grid = HeightGrid { origin, cell_size, nx, ny, heights, lipschitz: 0.0 };
        grid.lipschitz = grid.slope_bound();
        grid
    }

    /// Moves the grid by `by` (x, y of its samples, their elevations by z), in place: a DEM is
    /// never held twice.
    pub fn translate(&mut self, by: [f64; 3]) {
        self.origin = [self.origin[0] + by[0], self.origin[1] + by[1]];
        self.heights.iter_mut().for_each(|h| *h += by[2]);
        self.lipschitz = self.slope_bound();
    }

    fn at(&self, i: usize, j: usize) -> f64 {
        self.heights[j * self.nx as usize + i]
    }

    /// The Lipschitz bound of the bilinear interpolant over its valid cells, computed from the
    /// heights (what `lipschitz` holds for a grid made by [`HeightGrid::new`]).
    pub fn slope_bound(&self) -> f64 {
        let (nx, ny) = (self.nx as usize, self.ny as usize);
        let mut bound = 0.0f64;
        for j in 0..ny.saturating_sub(1) {
            for i in 0..nx.saturating_sub(1) {
                let (a, b, c, d) =
                    (self.at(i, j), self.at(i + 1, j), self.at(i, j + 1), self.at(i + 1, j + 1));
                let gx = (b - a).abs().max((d - c).abs()) / self.cell_size;
                let gy = (c - a).abs().max((d - b).abs()) / self.cell_size;
                let g = gx.hypot(gy);
                if g.is_finite() {
                    bound = bound.max(g);
                }
            }
        }
        bound
    }

    /// The x and y extent `[[x0, x1], [y0, y1]]` covered by the samples.
    pub fn extent(&self) -> [[f64; 2]; 2] {
        let span = |o: f64, n: u32| [o, o + (n.max(1) - 1) as f64 * self.cell_size];
        [span(self.origin[0], self.nx), span(self.origin[1], self.ny)]
    }

    /// The first sample without data in the rectangle [x0, x1] × [y0, y1], as (column, row
    /// from the south).
    pub fn first_hole(&self, x: [f64; 2], y: [f64; 2]) -> Option<(usize, usize)> {
        let range = |lo: f64, hi: f64, o: f64, n: u32| {
            let a = ((lo - o) / self.cell_size).floor().max(0.0) as usize;
            let b = (((hi - o) / self.cell_size).ceil().max(0.0) as usize).min(n as usize - 1);
            a..=b
        };
        let cols = range(x[0], x[1], self.origin[0], self.nx);
        range(y[0], y[1], self.origin[1], self.ny)
            .flat_map(|j| cols.clone().map(move |i| (i, j)))
            .find(|&(i, j)| !self.at(i, j).is_finite())
    }

    /// Bilinear elevation at (x, y); positions outside the grid take the nearest edge's value.
    pub fn height(&self, x: f64, y: f64) -> f64 {
        let locate = |v: f64, o: f64, n: u32| {
            let t = ((v - o) / self.cell_size).clamp(0.0, (n.max(2) - 1) as f64);
            let i = (t.floor() as usize).min(n.max(2) as usize - 2);
            (i.min(n as usize - 1), t - i as f64)
        };
        if self.nx < 2 || self.ny < 2 {
            return self.heights.first().copied().unwrap_or(f64::NAN);
        }
        let (i, fx) = locate(x, self.origin[0], self.nx);
        let (j, fy) = locate(y, self.origin[1], self.ny);
        let south = self.at(i, j) * (1.0 - fx) + self.at(i + 1, j) * fx;
        let north = self.at(i, j + 1) * (1.0 - fx) + self.at(i + 1, j + 1) * fx;
        south * (1.0 - fy) + north * fy
    }
}

/// Writes `grid` as a 16-bit grayscale PNG with value = (h − offset)/vertical_scale, rounded.
pub fn write_png(path: &Path, grid: &HeightGrid, offset: f64, vertical_scale: f64) -> std::io::Result<()> {
    let (w, h) = (grid.nx as usize, grid.ny as usize);
    let mut values = Vec::with_capacity(w * h);
    for row in (0..h).rev() {
        for col in 0..w {
            values.push(((grid.at(col, row) - offset) / vertical_scale).round().clamp(0.0, 65535.0) as u16);
        }
    }
    image::write_png16(path, grid.nx, grid.ny, &values)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn ramp() -> HeightGrid {
        // 4 × 3 samples, 10 m apart, h = 100 + 0.5 x + 0.2 y.
        let heights =
            (0..3).flat_map(|j| (0..4).map(move |i| 100.0 + 5.0 * i as f64 + 2.0 * j as f64)).collect();
        HeightGrid::new([0.0, 0.0], 10.0, 4, 3, heights)
    }

    #[test]
    fn bilinear_reproduces_a_plane_and_bounds_its_slope() {
        let g = ramp();
        assert!((g.height(13.0, 7.0) - (100.0 + 6.5 + 1.4)).abs() < 1e-9);
        assert!((g.lipschitz - 0.5f64.hypot(0.2)).abs() < 1e-12);
        assert_eq!(g.extent(), [[0.0, 30.0], [0.0, 20.0]]);
        assert!((g.height(-5.0, 30.0) - (100.0 + 4.0)).abs() < 1e-9, "clamped to the edge");
    }

    #[test]
    fn png_round_trip_keeps_rows_and_scale() {
        let path = std::env::temp_dir().join(format!("karst-hf-{}.png", std::process::id()));
        write_png(&path, &ramp(), 50.0, 0.01).unwrap();
        let geo = Georeference {
            origin: [0.0, 0.0],
            cell_size: 10.0,
            vertical_scale: 0.01,
            offset: 50.0,
            nodata: None,
        };
        let back = HeightGrid::read_png(&path, &geo).unwrap();
        assert_eq!(back.nx, 4);
        assert!((back.height(30.0, 20.0) - 119.0).abs() < 1e-9);
        assert!((back.height(0.0, 0.0) - 100.0).abs() < 1e-9);
        let holes = Georeference { nodata: Some(5000.0), ..geo };
        let with_hole = HeightGrid::read_png(&path, &holes).unwrap();
        assert_eq!(with_hole.first_hole([0.0, 30.0], [0.0, 20.0]), Some((0, 0)));
        std::fs::remove_file(&path).unwrap();
    }

    #[test]
    fn exr_heights_are_read_from_the_r_channel_north_row_first() {
        let path = std::env::temp_dir().join(format!("karst-hf-{}.exr", std::process::id()));
        // 3 × 2 pixels: h = 10·column + 100·(1 − row), so the south row (row 1) is lower.
        exr::prelude::write_rgba_file(&path, 3, 2, |x, y| {
            (10.0 * x as f32 + 100.0 * (1 - y as i32) as f32, 0.0, 0.0, 1.0)
        })
        .unwrap();
        let geo = Georeference {
            origin: [0.0, 0.0],
            cell_size: 5.0,
            vertical_scale: 1.0,
            offset: 2.0,
            nodata: None,
        };
        let g = HeightGrid::read(&path, &geo).unwrap();
        assert_eq!((g.nx, g.ny), (3, 2));
        assert!((g.height(0.0, 0.0) - 2.0).abs() < 1e-9);
        assert!((g.height(10.0, 5.0) - 122.0).abs() < 1e-9);
        std::fs::remove_file(&path).unwrap();
    }
}
