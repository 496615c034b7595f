//! GeoTIFF rasters (the `tiff` crate, with the GeoTIFF 1.1 tags written here): one band of
//! float32, north row first, in Deflate-compressed strips; georeferenced by ModelPixelScale and one ModelTiepoint (the
//! north-west corner of the north-west pixel, RasterPixelIsArea), the CRS by its EPSG code
//! in ProjectedCRSGeoKey, no data as the GDAL_NODATA tag (NaN pixels are written as
//! [`NODATA`]).
//!
//! A run without a CRS writes its rasters (on request) with the georeferencing tags but no
//! CRS key: GIS programs open them as an unknown projected CRS in metres.

use std::io::Cursor;

use tiff::encoder::colortype::Gray32Float;
use tiff::encoder::{Compression, DeflateLevel, TiffEncoder};
use tiff::tags::Tag;

use karst_geodata::crs::Epsg;
use karst_scene::params::ExportFormat;

use crate::ExportError;
use crate::folder::Folder;
use crate::frame::Frame;
use crate::rasters::RasterGrid;

/// The value of pixels without data.
pub const NODATA: f32 = -9999.0;
/// Rows per strip: strips of about 64 KB for the widths of map rasters.
const ROWS_PER_STRIP: u32 = 16;

/// The raster's CRS: an EPSG code, or none.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Crs(pub Option<u16>);

impl Crs {
    /// The CRS of a run (`EPSG:NNNN`); GeoTIFF keys hold codes below 65536.
    pub fn of(crs: Option<&str>) -> Result<Crs, ExportError> {
        let Some(text) = crs else { return Ok(Crs(None)) };
        let epsg = Epsg::parse(text).map_err(|e| ExportError::Unsupported(format!("crs: {e}")))?;
        let code = u16::try_from(epsg.0)
            .map_err(|_| ExportError::Unsupported(format!("crs: {epsg} does not fit a GeoTIFF key")))?;
        Ok(Crs(Some(code)))
    }
}

/// Where a raster lies: its size, world corner, pixel size and CRS.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Placement {
    pub width: u32,
    pub height: u32,
    /// World `[x, y]` of the north-west corner of the north-west pixel.
    pub corner: [f64; 2],
    pub cell: f64,
    pub crs: Crs,
}

impl Placement {
    /// The placement of `grid` (local) in the world of `frame`.
    pub fn of(grid: &RasterGrid, frame: &Frame, crs: Crs) -> Placement {
        let [ox, oy, _] = frame.origin();
        let half = grid.cell / 2.0;
        Placement {
            width: grid.nx as u32,
            height: grid.ny as u32,
            corner: [
                grid.origin[0] - half + ox,
                grid.origin[1] + (grid.ny as f64 - 1.0) * grid.cell + half + oy,
            ],
            cell: grid.cell,
            crs,
        }
    }
}

/// Writes `values` (x fastest, south row first; NaN: no data) as the GeoTIFF `name`.
pub fn write(folder: &mut Folder, name: &str, place: &Placement, values: &[f32]) -> Result<(), ExportError> {
    let bytes = encode(place, values).map_err(|e| ExportError::Write {
        path: name.into(),
        source: std::io::Error::other(e.to_string()),
    })?;
    folder.write(name, ExportFormat::Geotiff, |w| w.write_all(&bytes))
}

/// The GeoTIFF file of `values`.
pub fn encode(place: &Placement, values: &[f32]) -> tiff::TiffResult<Vec<u8>> {
    let (width, height) = (place.width as usize, place.height as usize);
    assert_eq!(values.len(), width * height, "one value per pixel");
    let north_first: Vec<f32> = (0..height)
        .rev()
        .flat_map(|j| values[j * width..(j + 1) * width].iter().map(|v| if v.is_nan() { NODATA } else { *v }))
        .collect();
    let mut bytes = Cursor::new(Vec::new());
    let mut encoder =
        TiffEncoder::new(&mut bytes)?.with_compression(Compression::Deflate(DeflateLevel::Balanced));
    let mut image = encoder.new_image::<Gray32Float>(place.width, place.height)?;
    image.rows_per_strip(ROWS_PER_STRIP)?;
    let dir = image.encoder();
    dir.write_tag(Tag::ModelPixelScaleTag, &[place.cell, place.cell, 0.0][..])?;
    dir.write_tag(Tag::ModelTiepointTag, &[0.0, 0.0, 0.0, place.corner[0], place.corner[1], 0.0][..])?;
    dir.write_tag(Tag::GeoKeyDirectoryTag, &geo_keys(place.crs)[..])?;
    dir.write_tag(Tag::GdalNodata, &format!("{NODATA}")[..])?;
    image.write_data(&north_first)?;
    Ok(bytes.into_inner())
}

/// The GeoKey directory: version 1.1.0, then (key, location, count, value) entries sorted by
/// key: GTModelType projected (1), GTRasterType PixelIsArea (1), ProjectedCRS (the EPSG code,
/// or user-defined 32767 without one).
fn geo_keys(crs: Crs) -> Vec<u16> {
    let projected = crs.0.unwrap_or(32767);
    vec![1, 1, 0, 3, 1024, 0, 1, 1, 1025, 0, 1, 1, 3072, 0, 1, projected]
}

#[cfg(test)]
mod tests {
    use super::*;
    use tiff::decoder::{Decoder, DecodingResult};

    #[test]
    fn a_raster_reads_back_north_row_first_with_its_tags() {
        let place =
            Placement { width: 3, height: 2, corner: [1000.0, 2000.0], cell: 10.0, crs: Crs(Some(2154)) };
        // South row 0, 1, 2; north row 3, NaN, 5.
        let bytes = encode(&place, &[0.0, 1.0, 2.0, 3.0, f32::NAN, 5.0]).unwrap();
        let mut decoder = Decoder::new(Cursor::new(bytes)).unwrap();
        let DecodingResult::F32(values) = decoder.read_image().unwrap() else { panic!("float32") };
        assert_eq!(values, [3.0, NODATA, 5.0, 0.0, 1.0, 2.0]);
        let keys = decoder.get_tag_u16_vec(Tag::GeoKeyDirectoryTag).unwrap();
        assert_eq!(keys[keys.len() - 4..], [3072, 0, 1, 2154]);
        let tie = decoder.get_tag_f64_vec(Tag::ModelTiepointTag).unwrap();
        assert_eq!(tie[3..5], [1000.0, 2000.0]);
        assert_eq!(decoder.get_tag_ascii_string(Tag::GdalNodata).unwrap(), "-9999");
    }
}
