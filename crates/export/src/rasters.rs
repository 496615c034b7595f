//! The conduits as map rasters: the grid they are computed on and what each pixel holds.
//!
//! The grid ([`RasterGrid`]): the terrain's own when the terrain is a raster (a GeoTIFF or a
//! heightfield image: one pixel centred on each elevation sample, so that a GIS overlays the
//! rasters on the DEM pixel for pixel), cropped to the pixels that overlap the domain;
//! otherwise square pixels of `[export] raster_cell` metres (default: the domain's longer
//! horizontal side / [`DEFAULT_PIXELS`]) from the domain's south-west corner.
//!
//! What a pixel holds ([`ConduitMaps`], values at the pixel's centre):
//!
//! - depth: the ground elevation at the pixel's centre minus the highest conduit roof whose
//!   footprint covers part of the pixel ([`crate::footprint`]), metres; no data where no
//!   footprint does;
//! - density: the length of conduit centreline inside the pixel (3D length of the part of
//!   each segment whose map projection lies in the pixel), in metres per km²; 0 where none.
//!
//! An ensemble's rasters come from per-realization [`Columns`]: for each covered pixel, the
//! depths below ground of the conduits over it (merged intervals), from which the share of
//! realizations with a conduit at any depth or within a depth band follows.

use serde::{Deserialize, Serialize};

use karst_geology::{Domain, Terrain};

use crate::ExportError;
use crate::footprint::SegmentFootprint;
use crate::network::NetworkView;

/// The default grid's pixels along the domain's longer horizontal side.
pub const DEFAULT_PIXELS: f64 = 500.0;
/// Largest raster, in pixels (a 4 GB f32 GeoTIFF is not a map).
pub const MAX_PIXELS: u64 = 100_000_000;

/// A north-up grid of square pixels, in local coordinates.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct RasterGrid {
    /// Centre `[x, y]` of the south-west pixel.
    pub origin: [f64; 2],
    /// Pixel edge, metres.
    pub cell: f64,
    pub nx: usize,
    pub ny: usize,
}

impl RasterGrid {
    /// The grid of a run's rasters (see the module doc).
    pub fn of(
        terrain: &Terrain,
        domain: &Domain,
        raster_cell: Option<f64>,
    ) -> Result<RasterGrid, ExportError> {
        let grid = match (terrain, raster_cell) {
            (Terrain::Heightfield { grid, .. }, None) if grid.nx > 0 && grid.ny > 0 => {
                let cell = grid.cell_size;
                // Pixels [o + (i - ½)c, o + (i + ½)c] that overlap [lo, hi].
                let span = |o: f64, n: u32, lo: f64, hi: f64| {
                    let first = ((lo - o) / cell - 0.5).floor() + 1.0;
                    let last = ((hi - o) / cell + 0.5).ceil() - 1.0;
                    let (first, last) = (first.max(0.0), last.min(f64::from(n) - 1.0));
                    (first, (last - first + 1.0).max(0.0))
                };
                let (i0, nx) = span(grid.origin[0], grid.nx, domain.min[0], domain.max[0]);
                let (j0, ny) = span(grid.origin[1], grid.ny, domain.min[1], domain.max[1]);
                RasterGrid {
                    origin: [grid.origin[0] + i0 * cell, grid.origin[1] + j0 * cell],
                    cell,
                    nx: nx as usize,
                    ny: ny as usize,
                }
            }
            _ => {
                let side = [domain.max[0] - domain.min[0], domain.max[1] - domain.min[1]];
                let cell = raster_cell.unwrap_or(side[0].max(side[1]) / DEFAULT_PIXELS);
                let count = |s: f64| (s / cell).ceil().max(1.0);
                let (nx, ny) = (count(side[0]), count(side[1]));
                if nx * ny > MAX_PIXELS as f64 {
                    return Err(ExportError::Unsupported(format!(
                        "export.raster_cell: {cell} m pixels make a raster of {nx} × {ny} pixels, more than {MAX_PIXELS}: choose larger pixels"
                    )));
                }
                RasterGrid {
                    origin: [domain.min[0] + cell / 2.0, domain.min[1] + cell / 2.0],
                    cell,
                    nx: nx as usize,
                    ny: ny as usize,
                }
            }
        };
        if grid.nx == 0 || grid.ny == 0 {
            return Err(ExportError::Unsupported(
                "terrain: the heightfield has no pixel over the domain".into(),
            ));
        }
        Ok(grid)
    }

    /// Number of pixels.
    pub fn len(&self) -> usize {
        self.nx * self.ny
    }

    /// Whether the grid has no pixel.
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// The centre of pixel (column i, row j from the south).
    pub fn centre(&self, i: usize, j: usize) -> [f64; 2] {
        [self.origin[0] + i as f64 * self.cell, self.origin[1] + j as f64 * self.cell]
    }

    /// The pixel index (x fastest, south row first) of pixel (i, j).
    pub fn index(&self, i: usize, j: usize) -> usize {
        j * self.nx + i
    }

    /// The columns and rows whose centres lie in the map box `[min, max]`.
    fn centres_in(&self, [min, max]: [[f64; 2]; 2]) -> (std::ops::Range<usize>, std::ops::Range<usize>) {
        let range = |lo: f64, hi: f64, o: f64, n: usize| {
            let a = ((lo - o) / self.cell).ceil().max(0.0);
            let b = ((hi - o) / self.cell).floor().min(n as f64 - 1.0);
            if b < a { 0..0 } else { a as usize..b as usize + 1 }
        };
        (range(min[0], max[0], self.origin[0], self.nx), range(min[1], max[1], self.origin[1], self.ny))
    }

    /// The pixel holding the map point (x, y), if any.
    fn pixel_of(&self, x: f64, y: f64) -> Option<usize> {
        let i = ((x - self.origin[0]) / self.cell + 0.5).floor();
        let j = ((y - self.origin[1]) / self.cell + 0.5).floor();
        let inside = i >= 0.0 && j >= 0.0 && i < self.nx as f64 && j < self.ny as f64;
        inside.then(|| self.index(i as usize, j as usize))
    }

    /// Ground elevation at every pixel centre.
    pub fn ground(&self, terrain: &Terrain) -> Vec<f64> {
        (0..self.ny)
            .flat_map(|j| (0..self.nx).map(move |i| (i, j)))
            .map(|(i, j)| {
                let [x, y] = self.centre(i, j);
                terrain.height(x, y)
            })
            .collect()
    }
}

/// The single run's rasters, x fastest, south row first; NaN is no data.
#[derive(Debug, Clone, PartialEq)]
pub struct ConduitMaps {
    pub depth: Vec<f32>,
    pub density: Vec<f32>,
}

impl ConduitMaps {
    /// Depth and density of the network's conduits on `grid`.
    pub fn of(grid: &RasterGrid, terrain: &Terrain, net: &NetworkView) -> ConduitMaps {
        let ground = grid.ground(terrain);
        let footprints = SegmentFootprint::all(net);
        let columns = Columns::of(grid, &ground, &footprints);
        let mut depth = vec![f32::NAN; grid.len()];
        for (pixel, spans) in &columns.pixels {
            depth[*pixel as usize] = spans[0][0];
        }
        ConduitMaps { depth, density: density(grid, &footprints) }
    }
}

/// Conduit centreline length in each pixel, m per km².
fn density(grid: &RasterGrid, segments: &[SegmentFootprint]) -> Vec<f32> {
    let mut metres = vec![0.0f64; grid.len()];
    for s in segments {
        let [a, b] = s.ends;
        let length = (0..3).map(|i| (b[i] - a[i]).powi(2)).sum::<f64>().sqrt();
        // The parameters where the projection crosses a pixel edge split the segment into
        // pieces that each lie in one pixel.
        let mut cuts = vec![0.0, 1.0];
        for axis in 0..2 {
            let (from, to) = (a[axis], b[axis]);
            if from == to {
                continue;
            }
            // Pixel edges k (between pixels k − 1 and k) crossed, within the grid's.
            let edge = |v: f64| (v - grid.origin[axis]) / grid.cell + 0.5;
            let last = [grid.nx, grid.ny][axis] as f64;
            let (lo, hi) = (edge(from.min(to)).ceil().max(0.0), edge(from.max(to)).floor().min(last));
            let mut k = lo;
            while k <= hi {
                let v = grid.origin[axis] + (k - 0.5) * grid.cell;
                cuts.push((v - from) / (to - from));
                k += 1.0;
            }
        }
        cuts.sort_by(f64::total_cmp);
        for w in cuts.windows(2) {
            let t = (w[0] + w[1]) / 2.0;
            let x = a[0] + (b[0] - a[0]) * t;
            let y = a[1] + (b[1] - a[1]) * t;
            if let Some(pixel) = grid.pixel_of(x, y) {
                metres[pixel] += length * (w[1] - w[0]);
            }
        }
    }
    let km2 = grid.cell * grid.cell / 1e6;
    metres.iter().map(|m| (m / km2) as f32).collect()
}

/// The conduits over each pixel of one realization: for every pixel a footprint covers, the
/// depths below ground `[top, bottom]` of the conduit sections over it, merged where they
/// overlap and sorted from the shallowest. What an ensemble records per realization.
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
pub struct Columns {
    /// (pixel index, depth spans), by pixel index.
    pub pixels: Vec<(u32, Vec<[f32; 2]>)>,
}

impl Columns {
    /// The columns of the `footprints` on `grid`, `ground` being the ground elevation at each
    /// pixel centre (pixels without ground are left out).
    pub fn of(grid: &RasterGrid, ground: &[f64], footprints: &[SegmentFootprint]) -> Columns {
        let mut spans: std::collections::BTreeMap<u32, Vec<[f64; 2]>> = std::collections::BTreeMap::new();
        for footprint in footprints {
            let [min, max] = footprint.bounds();
            let half = grid.cell / 2.0;
            let (columns, rows) = grid.centres_in([min.map(|v| v - half), max.map(|v| v + half)]);
            for j in rows {
                for i in columns.clone() {
                    let [x, y] = grid.centre(i, j);
                    let pixel = grid.index(i, j);
                    let (Some(c), true) = (footprint.over_pixel(x, y, half), ground[pixel].is_finite())
                    else {
                        continue;
                    };
                    spans
                        .entry(pixel as u32)
                        .or_default()
                        .push([ground[pixel] - c.roof, ground[pixel] - c.floor]);
                }
            }
        }
        let pixels = spans.into_iter().map(|(pixel, list)| (pixel, merge(list))).collect();
        Columns { pixels }
    }

    /// Whether the pixel's spans reach into the depth band `[min, max]` (any depth: None).
    pub fn within(spans: &[[f32; 2]], band: Option<[f64; 2]>) -> bool {
        match band {
            None => !spans.is_empty(),
            Some([min, max]) => spans.iter().any(|s| f64::from(s[0]) <= max && f64::from(s[1]) >= min),
        }
    }
}

/// Sorted, disjoint spans covering the same depths.
fn merge(mut list: Vec<[f64; 2]>) -> Vec<[f32; 2]> {
    list.sort_by(|a, b| a[0].total_cmp(&b[0]));
    let mut merged: Vec<[f64; 2]> = Vec::with_capacity(list.len());
    for span in list {
        match merged.last_mut() {
            Some(last) if span[0] <= last[1] => last[1] = last[1].max(span[1]),
            _ => merged.push(span),
        }
    }
    merged.into_iter().map(|s| s.map(|v| v as f32)).collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn spans_merge_and_bands_test_them() {
        let spans = merge(vec![[5.0, 7.0], [1.0, 3.0], [2.0, 4.0]]);
        assert_eq!(spans, [[1.0, 4.0], [5.0, 7.0]]);
        assert!(Columns::within(&spans, None));
        assert!(Columns::within(&spans, Some([4.5, 5.5])));
        assert!(!Columns::within(&spans, Some([4.2, 4.8])));
        assert!(!Columns::within(&[], None));
    }

    #[test]
    fn density_shares_a_segment_between_the_pixels_it_crosses() {
        let grid = RasterGrid { origin: [5.0, 5.0], cell: 10.0, nx: 3, ny: 2 };
        // From x 5 to 25 at y 5 (the centres of pixels 0 and 2), rising 20 m: its 3D length
        // √2 · 20 splits 1/4, 1/2, 1/4 over pixels 0, 1, 2; the shaft's 30 m go to pixel 4.
        let rising = SegmentFootprint { ends: [[5.0, 5.0, 0.0], [25.0, 5.0, 20.0]], radius: [1.0, 1.0] };
        let shaft = SegmentFootprint { ends: [[15.0, 15.0, 0.0], [15.0, 15.0, 30.0]], radius: [1.0, 1.0] };
        let outside = SegmentFootprint { ends: [[-1e9, 5.0, 0.0], [-1e8, 5.0, 0.0]], radius: [1.0, 1.0] };
        let per_km2 = density(&grid, &[rising, shaft, outside]);
        let metres: Vec<f32> = per_km2.iter().map(|d| d * 1e-4).collect();
        let full = 20.0 * std::f32::consts::SQRT_2;
        let expected = [full / 4.0, full / 2.0, full / 4.0, 0.0, 30.0, 0.0];
        assert!(metres.iter().zip(expected).all(|(m, e)| (m - e).abs() < 1e-3), "{metres:?}");
    }

    #[test]
    fn a_plane_terrain_gets_the_default_grid() {
        let terrain = Terrain::Plane { elevation: 100.0, origin: [0.0; 2], gradient: [0.0; 2] };
        let domain = Domain { min: [0.0, 0.0, 0.0], max: [1000.0, 400.0, 100.0] };
        let grid = RasterGrid::of(&terrain, &domain, None).unwrap();
        assert_eq!((grid.cell, grid.nx, grid.ny, grid.origin), (2.0, 500, 200, [1.0, 1.0]));
        let err = RasterGrid::of(&terrain, &domain, Some(0.01)).unwrap_err().to_string();
        assert!(err.contains("export.raster_cell"), "{err}");
    }
}
