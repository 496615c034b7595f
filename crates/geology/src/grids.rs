//! GeoTIFF rasters in the scene: the terrain as a bilinear [`HeightGrid`], and water tables,
//! horizons and faults given as elevation rasters as triangulated surfaces ([`Tin`]).
//!
//! The terrain is interpolated bilinearly between pixel centres (see [`karst_geodata::geotiff`] for
//! where a pixel's value stands). A surface needs exact distances and points exactly on it
//! (sampling, inception costs), which a bilinear patch does not give in closed form, so a
//! surface raster becomes a TIN through the same pixel centres: each cell between four centres
//! is split along its south-west–north-east diagonal. Both interpolants agree at the pixels and
//! differ inside a cell by at most a quarter of the cell's twist |h00 + h11 − h10 − h01|.

use crate::heightfield::HeightGrid;
use karst_geodata::geotiff::GeoRaster;
use karst_geodata::tin::TinError;

use crate::tin::Tin;

/// Does `file` name a GeoTIFF (by extension)?
pub fn is_geotiff(file: &str) -> bool {
    let lower = file.to_ascii_lowercase();
    lower.ends_with(".tif") || lower.ends_with(".tiff")
}

/// The terrain: elevation = offset + vertical_scale·value at each pixel centre (the raster's
/// values become the heights in place: a large DEM is held once).
pub fn height_grid(raster: GeoRaster, vertical_scale: f64, offset: f64) -> HeightGrid {
    let (origin, cell, nx, ny) = (raster.origin, raster.cell, raster.nx as u32, raster.ny as u32);
    let mut heights = raster.values;
    for h in &mut heights {
        *h = offset + vertical_scale * *h;
    }
    HeightGrid::new(origin, cell, nx, ny, heights)
}

/// A surface through the pixel centres, two triangles per cell.
pub fn tin(raster: &GeoRaster, file: &str) -> Result<Tin, TinError> {
    let (nx, ny) = (raster.nx, raster.ny);
    let mut vertices = Vec::with_capacity(nx * ny);
    for j in 0..ny {
        for i in 0..nx {
            let [x, y] = raster.position(i, j);
            vertices.push([x, y, raster.at(i, j)]);
        }
    }
    let mut triangles = Vec::with_capacity(2 * nx.saturating_sub(1) * ny.saturating_sub(1));
    for j in 0..ny.saturating_sub(1) {
        for i in 0..nx.saturating_sub(1) {
            let v = |di: usize, dj: usize| ((j + dj) * nx + i + di) as u32;
            triangles.push([v(0, 0), v(1, 0), v(1, 1)]);
            triangles.push([v(0, 0), v(1, 1), v(0, 1)]);
        }
    }
    Tin::new(vertices, triangles, file)
}

#[cfg(test)]
mod tests {
    use super::*;
    use karst_geodata::geotiff::testing::{Encoding, write};

    #[test]
    fn terrain_and_surface_agree_at_pixels_and_on_planes() {
        let path = std::env::temp_dir().join(format!("karst-grids-{}.tif", std::process::id()));
        // 4 × 3 pixels of 10 m holding a plane: the bilinear and triangulated surfaces coincide.
        let values: Vec<f32> =
            (0..3).flat_map(|r| (0..4).map(move |c| (5 * c + 3 * r) as f32 * 0.5)).collect();
        write(&path, 4, 3, &values, &Encoding::default()).unwrap();
        let raster = GeoRaster::read(&path, None, None).unwrap();
        let grid = height_grid(raster.clone(), 2.0, 100.0);
        let surface = tin(&raster, "wt.tif").unwrap();
        assert_eq!(surface.triangles.len(), 2 * 3 * 2);
        for (x, y) in [(1005.0, 5015.0), (1017.5, 5022.0), (1033.0, 5019.0)] {
            let bilinear = (grid.height(x, y) - 100.0) / 2.0;
            assert!((surface.elevation_at(x, y) - bilinear).abs() < 1e-9, "({x}, {y})");
        }
        assert_eq!(grid.height(1005.0, 5015.0), 100.0 + 2.0 * raster.at(0, 0));
        assert!(is_geotiff("data/DEM.TIF") && is_geotiff("wt.tiff") && !is_geotiff("dem.png"));
        std::fs::remove_file(&path).unwrap();
    }
}
