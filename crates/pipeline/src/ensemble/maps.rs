//! The ensemble's map rasters for a GIS: `probability.tif`, the share of realizations with a
//! conduit footprint over each pixel (at any depth, or within the depth band given with
//! `--depth-band MIN..MAX`, metres below ground), and `mean-depth.tif`, the mean over those
//! realizations of the depth below ground of their highest conduit roof over the pixel (no
//! data where none has one).
//!
//! The pixels are those of the single run's rasters (`karst_export::rasters::RasterGrid`:
//! the terrain's grid, or `[export] raster_cell`), placed in the world by the scene's frame.
//! Each realization records its footprint columns ([`Columns`]: the depth spans of its
//! conduits over every covered pixel) in its record, so that a merge of records from several
//! machines computes the same rasters, for any depth band.

use std::path::Path;

use serde::{Deserialize, Serialize};

use karst_artifact::Frame;
use karst_export::footprint::SegmentFootprint;
use karst_export::geotiff::{Crs, Placement, encode};
use karst_export::rasters::{Columns, RasterGrid};
use karst_export::{ExportError, NetworkView};
use karst_hydro::Hydro;
use karst_scene::Scene;
use karst_skeleton::Skeleton;
use karst_stage::StageError;

use super::record::Figures;
use crate::options::OptionError;

/// The rasters' grid and where it lies, as `ensemble.json` records it.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct MapGrid {
    /// The grid, in the scene's local coordinates.
    pub grid: RasterGrid,
    /// The local frame: the origin added back and the CRS of the GeoTIFFs.
    pub frame: Frame,
}

impl MapGrid {
    /// The map grid of `scene`.
    pub fn of(scene: &Scene) -> Result<MapGrid, StageError> {
        let grid = RasterGrid::of(scene.terrain(), scene.domain(), scene.export().raster_cell)
            .map_err(|e| StageError::input(format!("ensemble: {e}")))?;
        Ok(MapGrid { grid, frame: scene.frame().clone() })
    }

    /// The footprint columns of one realization: its hydro's conduit radii when hydro ran,
    /// else its skeleton's.
    pub fn columns(
        &self,
        scene: &Scene,
        skeleton: &Skeleton,
        hydro: Option<&Hydro>,
    ) -> Result<Columns, StageError> {
        let footprints = match hydro {
            Some(hydro) => SegmentFootprint::all(
                &NetworkView::new(skeleton, hydro)
                    .map_err(|e: ExportError| StageError::input(e.to_string()))?,
            ),
            None => SegmentFootprint::of_skeleton(skeleton),
        };
        let ground = self.grid.ground(scene.terrain());
        Ok(Columns::of(&self.grid, &ground, &footprints))
    }
}

/// A depth band `MIN..MAX` (metres below ground, MIN ≤ MAX), as `--depth-band` takes it.
pub fn parse_depth_band(text: &str) -> Result<[f64; 2], OptionError> {
    let bad = || OptionError::new("--depth-band", text, "not MIN..MAX in metres below ground (e.g. 0..50)");
    let (min, max) = text.split_once("..").ok_or_else(bad)?;
    let parse = |v: &str| v.trim().parse::<f64>().ok().filter(|v| v.is_finite());
    match (parse(min), parse(max)) {
        (Some(min), Some(max)) if min <= max => Ok([min, max]),
        _ => Err(bad()),
    }
}

/// Writes `probability.tif` and `mean-depth.tif` of the complete realizations into `out`.
pub fn write(
    out: &Path,
    map: &MapGrid,
    complete: &[(u64, &Figures)],
    band: Option<[f64; 2]>,
) -> Result<(), StageError> {
    let pixels = map.grid.len();
    let mut present = vec![0u32; pixels];
    let mut depth_sum = vec![0.0f64; pixels];
    let mut depth_count = vec![0u32; pixels];
    for (seed, figures) in complete {
        for (pixel, spans) in &figures.columns.pixels {
            let p = *pixel as usize;
            if p >= pixels || spans.is_empty() {
                return Err(StageError::input(format!(
                    "{}: the record of seed {seed} names pixel {pixel}, outside the {pixels}-pixel map grid",
                    out.display()
                )));
            }
            if Columns::within(spans, band) {
                present[p] += 1;
            }
            depth_sum[p] += f64::from(spans[0][0]);
            depth_count[p] += 1;
        }
    }
    let n = complete.len().max(1) as f64;
    let probability: Vec<f32> = present.iter().map(|&c| (f64::from(c) / n) as f32).collect();
    let mean_depth: Vec<f32> = depth_sum
        .iter()
        .zip(&depth_count)
        .map(|(s, &c)| if c == 0 { f32::NAN } else { (s / f64::from(c)) as f32 })
        .collect();
    let crs = Crs::of(map.frame.crs.as_deref()).map_err(|e| StageError::input(format!("ensemble: {e}")))?;
    let frame = karst_export::frame::Frame::new(map.frame.origin);
    let place = Placement::of(&map.grid, &frame, crs);
    for (name, values) in [("probability.tif", &probability), ("mean-depth.tif", &mean_depth)] {
        let path = out.join(name);
        let bytes =
            encode(&place, values).map_err(|e| StageError::failure(format!("{}: {e}", path.display())))?;
        karst_artifact::atomic::write_bytes(&path, &bytes)
            .map_err(|e| StageError::failure(format!("{}: cannot write: {e}", path.display())))?;
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn depth_bands_parse_or_name_the_option() {
        assert_eq!(parse_depth_band("0..50"), Ok([0.0, 50.0]));
        assert_eq!(parse_depth_band(" 10.5 .. 20 "), Ok([10.5, 20.0]));
        for bad in ["50..0", "0-50", "a..b", "..", "0..inf"] {
            assert!(parse_depth_band(bad).unwrap_err().to_string().contains("--depth-band"), "{bad}");
        }
    }
}
