//! GeoTIFF rasters: a DEM, a piezometric map or a horizon's elevation as a georeferenced grid,
//! read with the pure-Rust `tiff` crate and our own GeoKey reader ([`crate::geokeys`]).
//!
//! Supported: one band of 8, 16, 32 or 64-bit unsigned or signed integers or 16, 32 or 64-bit
//! floats, in strips or tiles, uncompressed, LZW or Deflate (with or without a predictor);
//! georeferenced by ModelPixelScale + one ModelTiepoint, or by a ModelTransformation without
//! rotation, with square pixels in metres; the CRS's EPSG code from ProjectedCRSGeoKey; no-data
//! from the GDAL_NODATA tag (or the scene's `nodata`), NaN pixels never have data.
//!
//! Sampling convention: a pixel's value stands at its centre. With RasterPixelIsArea (the
//! default) pixel (column c, row r) is the square [c, c+1) × [r, r+1) of raster space and its
//! centre is raster point (c + ½, r + ½); with RasterPixelIsPoint the pixel is raster point
//! (c, r) itself. The model coordinates of that point, through the tie point and pixel scale
//! (or the transformation), are where the value holds; values are interpolated bilinearly
//! between pixel centres. GDAL's `gdallocationinfo -geoloc X Y` at a pixel centre returns the
//! same pixel (GDAL moves point rasters' origin by half a pixel to the same effect).
//!
//! Only the window of pixels whose centres bracket the requested footprint (the domain) is
//! decoded, chunk by chunk; its size is checked against [`BUDGET_BYTES`] before anything is
//! allocated. The window must lie inside the raster and every pixel of it must have data.

use std::fs::File;
use std::io::BufReader;
use std::path::Path;

use tiff::decoder::{Decoder, DecodingResult, Limits};
use tiff::tags::{CompressionMethod, SampleFormat, Tag};

use crate::crs::Epsg;
use crate::geokeys::{self, GeoKeys};

/// Largest decoded window, in bytes of f64 values (plus the largest chunk being decoded):
/// 1 GiB, about a 11,500 × 11,500-pixel window.
pub const BUDGET_BYTES: u64 = 1 << 30;

/// A window of a GeoTIFF's band: values at pixel centres on a regular grid, south row first.
#[derive(Debug, Clone, PartialEq)]
pub struct GeoRaster {
    /// The CRS the file declares, if it declares one with an EPSG code.
    pub crs: Option<Epsg>,
    /// RasterPixelIsPoint (else RasterPixelIsArea).
    pub pixel_is_point: bool,
    /// Model coordinates `[x, y]` of the centre of the window's south-west pixel.
    pub origin: [f64; 2],
    /// Pixel size, metres (pixels are square).
    pub cell: f64,
    pub nx: usize,
    pub ny: usize,
    /// Values, x fastest, south row first; NaN where there is no data.
    pub values: Vec<f64>,
    /// The window's file pixels: the column of x index 0 and its step (±1), the row of y index
    /// 0 and its step (rows grow southwards in a north-up file).
    columns: (usize, isize),
    rows: (usize, isize),
}

/// Why a GeoTIFF cannot be used.
#[derive(Debug, thiserror::Error, PartialEq)]
pub enum GeoTiffError {
    #[error("cannot read {file}: {message}")]
    Read { file: String, message: String },
    #[error("{file}: {message}")]
    Unsupported { file: String, message: String },
    #[error("{file}: {message}")]
    Georeferencing { file: String, message: String },
    #[error(
        "{file}: its pixel centres cover x [{}, {}], y [{}, {}], not the domain's x [{}, {}], y [{}, {}]",
        raster[0][0], raster[0][1], raster[1][0], raster[1][1], wanted[0][0], wanted[0][1], wanted[1][0], wanted[1][1]
    )]
    NotCovering { file: String, raster: [[f64; 2]; 2], wanted: [[f64; 2]; 2] },
    #[error(
        "{file}: the domain needs a window of {columns} × {rows} pixels ({} MiB decoded), more than the {} MiB raster budget: crop the raster to the domain (gdal_translate -projwin) or resample it (gdalwarp -tr)",
        mib(*bytes), mib(*budget)
    )]
    Budget { file: String, columns: usize, rows: usize, bytes: u64, budget: u64 },
    #[error(
        "{file}: pixel (column {column}, row {row}) at ({x}, {y}) has no data (value {value}){}",
        under_domain()
    )]
    NoData { file: String, column: usize, row: usize, x: f64, y: f64, value: String },
}

fn mib(bytes: u64) -> String {
    format!("{:.1}", bytes as f64 / (1u64 << 20) as f64)
}

fn under_domain() -> &'static str {
    ", inside the domain's footprint: fill the hole (gdal_fillnodata) or shrink the domain"
}

/// An inclusive range of file columns or rows.
type Span = (usize, usize);

/// A rectangle `[[x0, x1], [y0, y1]]` of model coordinates the window must cover.
pub type Footprint = [[f64; 2]; 2];

/// Pixel centre positions: model (x, y) = (x0 + (column + h)·dx, y0 + (row + h)·dy), h = ½ for
/// areas and 0 for points.
#[derive(Debug, Clone, Copy)]
struct Affine {
    x0: f64,
    y0: f64,
    dx: f64,
    dy: f64,
    h: f64,
}

impl Affine {
    fn centre(&self, column: usize, row: usize) -> [f64; 2] {
        [self.x0 + (column as f64 + self.h) * self.dx, self.y0 + (row as f64 + self.h) * self.dy]
    }
}

/// How the samples are stored.
#[derive(Debug, Clone, Copy)]
struct Layout {
    width: usize,
    height: usize,
    bits: u16,
}

impl GeoRaster {
    /// Reads the window of `path` that covers `footprint` (the whole raster when None).
    /// `nodata` overrides the file's GDAL_NODATA.
    pub fn read(
        path: &Path,
        footprint: Option<Footprint>,
        nodata: Option<f64>,
    ) -> Result<GeoRaster, GeoTiffError> {
        GeoRaster::read_within(path, footprint, nodata, BUDGET_BYTES)
    }

    /// [`GeoRaster::read`] with a memory budget of `budget` bytes.
    pub fn read_within(
        path: &Path,
        footprint: Option<Footprint>,
        nodata: Option<f64>,
        budget: u64,
    ) -> Result<GeoRaster, GeoTiffError> {
        let file = path.display().to_string();
        let read_error =
            |e: &dyn std::fmt::Display| GeoTiffError::Read { file: file.clone(), message: e.to_string() };
        let handle = File::open(path).map_err(|e| read_error(&e))?;
        let mut decoder = Decoder::new(BufReader::new(handle)).map_err(|e| read_error(&e))?;
        let layout = layout(&mut decoder, &file)?;
        let keys = match tag_shorts(&mut decoder, Tag::GeoKeyDirectoryTag, &file)? {
            Some(directory) => GeoKeys::parse(&directory)
                .map_err(|e| GeoTiffError::Georeferencing { file: file.clone(), message: e.to_string() })?,
            None => GeoKeys::default(),
        };
        let crs = crs_of(&keys, &file)?;
        let affine = affine(&mut decoder, &keys, &file)?;
        let nodata = match nodata {
            Some(v) => Some(v),
            None => gdal_nodata(&mut decoder, &file)?,
        };
        let (columns, rows) = window(&layout, &affine, footprint, &file)?;
        let (nx, ny) = (columns.1 - columns.0 + 1, rows.1 - rows.0 + 1);
        let chunk = chunk_bytes(&decoder, &layout);
        let bytes = (nx as u64 * ny as u64).saturating_mul(8).saturating_add(chunk);
        if bytes > budget {
            return Err(GeoTiffError::Budget { file, columns: nx, rows: ny, bytes, budget });
        }
        // x grows with the column when dx > 0; y grows against the row when dy < 0 (north up).
        let column_step: isize = if affine.dx > 0.0 { 1 } else { -1 };
        let row_step: isize = if affine.dy < 0.0 { -1 } else { 1 };
        let first_column = if column_step > 0 { columns.0 } else { columns.1 };
        let first_row = if row_step > 0 { rows.0 } else { rows.1 };
        let mut raster = GeoRaster {
            crs,
            pixel_is_point: keys.pixel_is_point(),
            origin: affine.centre(first_column, first_row),
            cell: affine.dx.abs(),
            nx,
            ny,
            values: vec![f64::NAN; nx * ny],
            columns: (first_column, column_step),
            rows: (first_row, row_step),
        };
        let mut limits = Limits::default();
        limits.decoding_buffer_size = budget.min(usize::MAX as u64) as usize;
        let mut decoder = decoder.with_limits(limits);
        raster.decode(&mut decoder, &layout, (columns, rows), nodata).map_err(|e| read_error(&e))?;
        raster.check_holes(&affine, &file, nodata)?;
        Ok(raster)
    }

    /// The file's (column, row) of grid sample (i, j).
    pub fn pixel_of(&self, i: usize, j: usize) -> (usize, usize) {
        let at = |(first, step): (usize, isize), k: usize| (first as isize + step * k as isize) as usize;
        (at(self.columns, i), at(self.rows, j))
    }

    /// The value of grid sample (i, j) (x index, y index from the south).
    pub fn at(&self, i: usize, j: usize) -> f64 {
        self.values[j * self.nx + i]
    }

    /// Model coordinates of grid sample (i, j).
    pub fn position(&self, i: usize, j: usize) -> [f64; 2] {
        [self.origin[0] + i as f64 * self.cell, self.origin[1] + j as f64 * self.cell]
    }

    /// Decodes the chunks that meet the window into `values`.
    fn decode(
        &mut self,
        decoder: &mut Decoder<BufReader<File>>,
        layout: &Layout,
        (columns, rows): (Span, Span),
        nodata: Option<f64>,
    ) -> tiff::TiffResult<()> {
        let (chunk_w, chunk_h) = decoder.chunk_dimensions();
        let (chunk_w, chunk_h) = (chunk_w as usize, chunk_h as usize);
        let across = layout.width.div_ceil(chunk_w);
        for chunk_row in rows.0 / chunk_h..=rows.1 / chunk_h {
            for chunk_column in columns.0 / chunk_w..=columns.1 / chunk_w {
                let index = (chunk_row * across + chunk_column) as u32;
                let (data_w, data_h) = decoder.chunk_data_dimensions(index);
                let data = decoder.read_chunk(index)?;
                let (top, left) = (chunk_row * chunk_h, chunk_column * chunk_w);
                let row_range = rows.0.max(top)..=rows.1.min(top + data_h as usize - 1);
                let column_range = columns.0.max(left)..=columns.1.min(left + data_w as usize - 1);
                for row in row_range {
                    for column in column_range.clone() {
                        let v = sample(&data, (row - top) * data_w as usize + column - left, nodata);
                        let i = (column as isize - self.columns.0 as isize) * self.columns.1;
                        let j = (row as isize - self.rows.0 as isize) * self.rows.1;
                        self.values[j as usize * self.nx + i as usize] = v;
                    }
                }
            }
        }
        Ok(())
    }

    fn check_holes(&self, affine: &Affine, file: &str, nodata: Option<f64>) -> Result<(), GeoTiffError> {
        let Some(k) = self.values.iter().position(|v| v.is_nan()) else { return Ok(()) };
        let (column, row) = self.pixel_of(k % self.nx, k / self.nx);
        let [x, y] = affine.centre(column, row);
        let value = nodata.map_or("NaN".to_string(), |n| format!("{n}, the no-data value"));
        Err(GeoTiffError::NoData { file: file.into(), column, row, x, y, value })
    }
}

/// The sample at `k` of a decoded chunk, NaN when it is the no-data value. Integers compare
/// exactly with the no-data value, floats in their own precision (GDAL writes float32 no-data
/// values such as -3.4028235e38 as decimal text).
fn sample(data: &DecodingResult, k: usize, nodata: Option<f64>) -> f64 {
    let exact = |v: f64| if nodata == Some(v) { f64::NAN } else { v };
    match data {
        DecodingResult::U8(d) => exact(d[k] as f64),
        DecodingResult::U16(d) => exact(d[k] as f64),
        DecodingResult::U32(d) => exact(d[k] as f64),
        DecodingResult::U64(d) => exact(d[k] as f64),
        DecodingResult::I8(d) => exact(d[k] as f64),
        DecodingResult::I16(d) => exact(d[k] as f64),
        DecodingResult::I32(d) => exact(d[k] as f64),
        DecodingResult::I64(d) => exact(d[k] as f64),
        DecodingResult::F16(d) => float(d[k].to_f32(), nodata),
        DecodingResult::F32(d) => float(d[k], nodata),
        DecodingResult::F64(d) => {
            if nodata == Some(d[k]) {
                f64::NAN
            } else {
                d[k]
            }
        }
    }
}

fn float(v: f32, nodata: Option<f64>) -> f64 {
    if nodata.is_some_and(|n| n as f32 == v) { f64::NAN } else { v as f64 }
}

/// Band count, sample type and compression, refused when karstgen cannot read them.
fn layout(decoder: &mut Decoder<BufReader<File>>, file: &str) -> Result<Layout, GeoTiffError> {
    let unsupported = |message: String| GeoTiffError::Unsupported { file: file.into(), message };
    let read = |e: tiff::TiffError| GeoTiffError::Read { file: file.into(), message: e.to_string() };
    let (width, height) = decoder.dimensions().map_err(read)?;
    let bands = decoder.find_tag_unsigned::<u16>(Tag::SamplesPerPixel).map_err(read)?.unwrap_or(1);
    if bands != 1 {
        return Err(unsupported(format!(
            "has {bands} bands (samples per pixel); karstgen reads single-band rasters: extract one with gdal_translate -b 1"
        )));
    }
    let compression = decoder.find_tag_unsigned::<u16>(Tag::Compression).map_err(read)?.unwrap_or(1);
    if !matches!(CompressionMethod::from_u16(compression), Some(c) if [CompressionMethod::None, CompressionMethod::LZW, CompressionMethod::Deflate, CompressionMethod::OldDeflate].contains(&c))
    {
        return Err(unsupported(format!(
            "compression {compression} ({}) is not supported: use none, LZW or Deflate (gdal_translate -co COMPRESS=DEFLATE)",
            compression_name(compression)
        )));
    }
    let bits = decoder.find_tag_unsigned_vec::<u16>(Tag::BitsPerSample).map_err(read)?.unwrap_or(vec![1]);
    let format = decoder.find_tag_unsigned_vec::<u16>(Tag::SampleFormat).map_err(read)?.unwrap_or(vec![1]);
    let (bits, format) = (bits[0], SampleFormat::from_u16(format[0]));
    let ok = match format {
        Some(SampleFormat::Uint | SampleFormat::Int) => matches!(bits, 8 | 16 | 32 | 64),
        Some(SampleFormat::IEEEFP) => matches!(bits, 16 | 32 | 64),
        _ => false,
    };
    if !ok {
        let kind = format.map_or("an unknown sample format".into(), |f| format!("{f:?}"));
        return Err(unsupported(format!(
            "{bits}-bit samples of {kind} are not supported: use 8 to 64-bit integers or 16 to 64-bit floats (gdal_translate -ot Float32)"
        )));
    }
    Ok(Layout { width: width as usize, height: height as usize, bits })
}

fn compression_name(code: u16) -> &'static str {
    match code {
        2..=4 => "CCITT fax",
        6 | 7 => "JPEG",
        32773 => "PackBits",
        34887 => "LERC",
        34925 => "LZMA",
        50000 => "ZSTD",
        50001 => "WebP",
        _ => "unknown",
    }
}

/// Bytes of the largest chunk the decoder holds at once.
fn chunk_bytes(decoder: &Decoder<BufReader<File>>, layout: &Layout) -> u64 {
    let (w, h) = decoder.chunk_dimensions();
    w as u64 * h.min(layout.height as u32) as u64 * (layout.bits as u64 / 8)
}

/// The CRS of the GeoKeys: a projected CRS's EPSG code; geographic coordinates (degrees) and
/// units other than the metre are refused.
fn crs_of(keys: &GeoKeys, file: &str) -> Result<Option<Epsg>, GeoTiffError> {
    let refuse = |message: String| GeoTiffError::Georeferencing { file: file.into(), message };
    let geographic = keys.model_type == Some(2) || (keys.projected.is_none() && keys.geographic.is_some());
    if geographic {
        let code = keys.geographic.map_or("a geographic CRS".into(), |c| format!("EPSG:{c}"));
        return Err(refuse(format!(
            "is in geographic coordinates ({code}, degrees); karstgen works in metres: reproject it to a projected CRS (gdalwarp -t_srs EPSG:NNNN)"
        )));
    }
    for (key, units) in
        [("ProjLinearUnitsGeoKey", keys.linear_units), ("VerticalUnitsGeoKey", keys.vertical_units)]
    {
        if let Some(u) = units.filter(|u| *u != geokeys::METRE) {
            return Err(refuse(format!("{key} is {u}, not metres (9001): convert the raster to metres")));
        }
    }
    match keys.projected {
        Some(geokeys::USER_DEFINED) => Err(refuse(
            "has a user-defined projected CRS (no EPSG code): assign its EPSG code (gdal_edit.py -a_srs EPSG:NNNN)"
                .into(),
        )),
        Some(code) => Ok(Some(Epsg(code as u32))),
        None => Ok(None),
    }
}

/// Pixel centres from the tie point and pixel scale, or from the transformation.
fn affine(
    decoder: &mut Decoder<BufReader<File>>,
    keys: &GeoKeys,
    file: &str,
) -> Result<Affine, GeoTiffError> {
    let refuse = |message: String| GeoTiffError::Georeferencing { file: file.into(), message };
    let scale = tag_doubles(decoder, Tag::ModelPixelScaleTag, file)?;
    let ties = tag_doubles(decoder, Tag::ModelTiepointTag, file)?;
    let transform = tag_doubles(decoder, Tag::ModelTransformationTag, file)?;
    let h = if keys.pixel_is_point() { 0.0 } else { 0.5 };
    let affine = match (scale, ties, transform) {
        (Some(scale), Some(ties), None) => {
            if scale.len() < 2 || ties.len() != 6 {
                return Err(refuse(format!(
                    "has {} tie points and {} scale values: karstgen reads one tie point with a pixel scale (warp control-point rasters with gdalwarp)",
                    ties.len() / 6,
                    scale.len()
                )));
            }
            let (dx, dy) = (scale[0], -scale[1]);
            Affine { x0: ties[3] - ties[0] * dx, y0: ties[4] - ties[1] * dy, dx, dy, h }
        }
        (None, None, Some(m)) => {
            if m.len() != 16 {
                return Err(refuse(format!("ModelTransformation has {} values, not 16", m.len())));
            }
            if m[1] != 0.0 || m[4] != 0.0 {
                return Err(refuse(format!(
                    "is rotated or sheared (ModelTransformation terms {} and {}): resample it north-up (gdalwarp)",
                    m[1], m[4]
                )));
            }
            Affine { x0: m[3], y0: m[7], dx: m[0], dy: m[5], h }
        }
        (None, None, None) | (None, Some(_), None) | (Some(_), None, None) => {
            return Err(refuse(
                "has no georeferencing (ModelPixelScale with ModelTiepoint, or ModelTransformation): georeference it (gdal_translate -a_ullr ULX ULY LRX LRY -a_srs EPSG:NNNN)".into(),
            ));
        }
        _ => {
            return Err(refuse(
                "has both a tie point with a pixel scale and a ModelTransformation; keep one".into(),
            ));
        }
    };
    let finite = [affine.x0, affine.y0, affine.dx, affine.dy].iter().all(|v| v.is_finite());
    if !finite || affine.dx == 0.0 || affine.dy == 0.0 {
        return Err(refuse(format!("pixel size {} × {} or origin is not usable", affine.dx, affine.dy)));
    }
    if (affine.dx.abs() - affine.dy.abs()).abs() > 1e-9 * affine.dx.abs() {
        return Err(refuse(format!(
            "has pixels of {} × {} m; karstgen needs square pixels: resample (gdalwarp -tr {} {})",
            affine.dx.abs(),
            affine.dy.abs(),
            affine.dx.abs(),
            affine.dx.abs()
        )));
    }
    Ok(affine)
}

/// The GDAL_NODATA tag's value (`"nan"` included).
fn gdal_nodata(decoder: &mut Decoder<BufReader<File>>, file: &str) -> Result<Option<f64>, GeoTiffError> {
    let read = |e: tiff::TiffError| GeoTiffError::Read { file: file.into(), message: e.to_string() };
    let Some(value) = decoder.find_tag(Tag::GdalNodata).map_err(read)? else { return Ok(None) };
    let text = value.into_string().map_err(read)?;
    let text = text.trim_matches(|c: char| c == '\0' || c.is_whitespace());
    text.parse::<f64>().map(Some).map_err(|_| GeoTiffError::Unsupported {
        file: file.into(),
        message: format!("GDAL_NODATA \"{text}\" is not a number"),
    })
}

fn tag_doubles(
    decoder: &mut Decoder<BufReader<File>>,
    tag: Tag,
    file: &str,
) -> Result<Option<Vec<f64>>, GeoTiffError> {
    tag_values(decoder, tag, file, tiff::decoder::ifd::Value::into_f64_vec)
}

fn tag_shorts(
    decoder: &mut Decoder<BufReader<File>>,
    tag: Tag,
    file: &str,
) -> Result<Option<Vec<u16>>, GeoTiffError> {
    tag_values(decoder, tag, file, tiff::decoder::ifd::Value::into_u16_vec)
}

/// The values of `tag` if the file has it, converted by `into`.
fn tag_values<T>(
    decoder: &mut Decoder<BufReader<File>>,
    tag: Tag,
    file: &str,
    into: fn(tiff::decoder::ifd::Value) -> tiff::TiffResult<Vec<T>>,
) -> Result<Option<Vec<T>>, GeoTiffError> {
    let read =
        |e: tiff::TiffError| GeoTiffError::Read { file: file.into(), message: format!("{tag:?}: {e}") };
    decoder.find_tag(tag).map_err(read)?.map(|v| into(v).map_err(read)).transpose()
}

/// The columns and rows (inclusive ranges) whose centres bracket `footprint`.
fn window(
    layout: &Layout,
    affine: &Affine,
    footprint: Option<Footprint>,
    file: &str,
) -> Result<(Span, Span), GeoTiffError> {
    let (w, h) = (layout.width, layout.height);
    let Some(wanted) = footprint else { return Ok(((0, w - 1), (0, h - 1))) };
    // Continuous column (row) of the centre at x (y); a pixel's tolerance against rounding.
    let span = |[a, b]: [f64; 2], origin: f64, step: f64| {
        let (ta, tb) = ((a - origin) / step - affine.h, (b - origin) / step - affine.h);
        ((ta.min(tb) + 1e-9).floor(), (ta.max(tb) - 1e-9).ceil())
    };
    let (c0, c1) = span(wanted[0], affine.x0, affine.dx);
    let (r0, r1) = span(wanted[1], affine.y0, affine.dy);
    if c0 < 0.0 || r0 < 0.0 || c1 > (w - 1) as f64 || r1 > (h - 1) as f64 {
        let [a, b] = [affine.centre(0, 0), affine.centre(w - 1, h - 1)];
        let raster = [[a[0].min(b[0]), a[0].max(b[0])], [a[1].min(b[1]), a[1].max(b[1])]];
        return Err(GeoTiffError::NotCovering { file: file.into(), raster, wanted });
    }
    let widen = |lo: f64, hi: f64, n: usize| {
        let (lo, hi) = (lo as usize, hi as usize);
        if lo < hi || n < 2 {
            (lo, hi)
        } else if hi + 1 < n {
            (lo, hi + 1)
        } else {
            (lo - 1, hi)
        }
    };
    Ok((widen(c0, c1, w), widen(r0, r1, h)))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geotiff::testing::{Encoding, write};

    fn temp(name: &str) -> std::path::PathBuf {
        std::env::temp_dir().join(format!("karst-geotiff-{}-{name}.tif", std::process::id()))
    }

    /// 5 × 4 pixels of 10 m, upper-left corner at (1000, 5040): value = 100·column + row.
    fn ramp() -> (Vec<f32>, Encoding) {
        let values = (0..4).flat_map(|r| (0..5).map(move |c| (100 * c + r) as f32)).collect();
        (values, Encoding::default())
    }

    #[test]
    fn pixel_centres_hold_the_values_south_row_first() {
        let path = temp("ramp");
        let (values, enc) = ramp();
        write(&path, 5, 4, &values, &enc).unwrap();
        let r = GeoRaster::read(&path, None, None).unwrap();
        assert_eq!((r.nx, r.ny, r.cell), (5, 4, 10.0));
        assert_eq!(r.origin, [1005.0, 5005.0], "centre of the south-west pixel");
        assert_eq!(r.at(0, 0), 3.0, "row 3 is the south row");
        assert_eq!(r.at(4, 3), 400.0);
        assert_eq!(r.pixel_of(4, 0), (4, 3));
        assert_eq!(r.crs, Some(Epsg(2154)));
        std::fs::remove_file(&path).unwrap();
    }

    #[test]
    fn pixel_is_point_moves_the_centres_by_half_a_pixel() {
        let path = temp("point");
        let (values, enc) = ramp();
        write(&path, 5, 4, &values, &Encoding { pixel_is_point: true, ..enc }).unwrap();
        let r = GeoRaster::read(&path, None, None).unwrap();
        assert!(r.pixel_is_point);
        assert_eq!(r.origin, [1000.0, 5010.0]);
        std::fs::remove_file(&path).unwrap();
    }

    #[test]
    fn the_window_brackets_the_footprint() {
        let path = temp("window");
        let (values, enc) = ramp();
        write(&path, 5, 4, &values, &enc).unwrap();
        let r = GeoRaster::read(&path, Some([[1016.0, 1024.0], [5011.0, 5014.0]]), None).unwrap();
        assert_eq!((r.nx, r.ny), (2, 2), "centres 1015 and 1025, 5005 and 5015");
        assert_eq!(r.origin, [1015.0, 5005.0]);
        assert_eq!(r.at(0, 0), 103.0);
        assert_eq!(r.pixel_of(1, 1), (2, 2));
        let outside = GeoRaster::read(&path, Some([[990.0, 1020.0], [5010.0, 5020.0]]), None).unwrap_err();
        assert!(
            matches!(outside, GeoTiffError::NotCovering { raster, .. } if raster == [[1005.0, 1045.0], [5005.0, 5035.0]])
        );
        std::fs::remove_file(&path).unwrap();
    }

    #[test]
    fn nodata_pixels_in_the_window_are_errors() {
        let path = temp("nodata");
        let (mut values, enc) = ramp();
        values[7] = -9999.0; // column 2, row 1
        write(&path, 5, 4, &values, &Encoding { nodata: Some("-9999".into()), ..enc }).unwrap();
        let e = GeoRaster::read(&path, None, None).unwrap_err();
        assert!(
            matches!(&e, GeoTiffError::NoData { column: 2, row: 1, x, y, .. } if (*x, *y) == (1025.0, 5025.0))
        );
        assert!(e.to_string().contains("value -9999, the no-data value"), "{e}");
        assert!(
            GeoRaster::read(&path, Some([[1035.0, 1045.0], [5005.0, 5035.0]]), None).is_ok(),
            "hole outside"
        );
        std::fs::remove_file(&path).unwrap();
    }

    #[test]
    fn georeferencing_problems_are_named() {
        let path = temp("georef");
        let (values, enc) = ramp();
        let cases: [(Encoding, &str); 4] = [
            (Encoding { scale: None, ..enc.clone() }, "has no georeferencing"),
            (Encoding { scale: Some([10.0, 12.5]), ..enc.clone() }, "pixels of 10 × 12.5 m"),
            (
                Encoding { scale: None, transform: Some([10.0, 2.0, -10.0]), ..enc.clone() },
                "rotated or sheared",
            ),
            (Encoding { epsg: Some((2, 4326)), ..enc.clone() }, "geographic coordinates (EPSG:4326"),
        ];
        for (encoding, expected) in cases {
            write(&path, 5, 4, &values, &encoding).unwrap();
            let e = GeoRaster::read(&path, None, None).unwrap_err();
            assert!(matches!(e, GeoTiffError::Georeferencing { .. }), "{e}");
            assert!(e.to_string().contains(expected), "{e} lacks {expected}");
        }
        std::fs::remove_file(&path).unwrap();
    }

    #[test]
    fn the_budget_is_checked_before_decoding() {
        let path = temp("budget");
        let (values, enc) = ramp();
        write(&path, 5, 4, &values, &enc).unwrap();
        // 5 × 4 values of 8 bytes and one strip of 2 rows of 5 float32: 160 + 40 bytes.
        let fits = GeoRaster::read_within(&path, None, None, 200);
        assert!(fits.is_ok(), "{fits:?}");
        let e = GeoRaster::read_within(&path, None, None, 199).unwrap_err();
        assert_eq!(
            e,
            GeoTiffError::Budget {
                file: path.display().to_string(),
                columns: 5,
                rows: 4,
                bytes: 200,
                budget: 199
            }
        );
        assert!(
            e.to_string().contains("5 × 4 pixels (0.0 MiB decoded), more than the 0.0 MiB raster budget"),
            "{e}"
        );
        std::fs::remove_file(&path).unwrap();
    }
}

/// Writing small GeoTIFFs for tests and example data: strips of one band, with the tags a
/// GeoTIFF writer sets.
pub mod testing {
    use std::path::Path;

    use tiff::encoder::colortype::Gray32Float;
    use tiff::encoder::{Compression, TiffEncoder};
    use tiff::tags::Tag;

    /// How to write the test raster.
    #[derive(Clone)]
    pub struct Encoding {
        /// Upper-left corner of the upper-left pixel (tie point of raster point (0, 0)).
        pub corner: [f64; 2],
        /// Pixel scale; None writes no scale nor tie point.
        pub scale: Option<[f64; 2]>,
        /// `[a, b, e]` of a ModelTransformation (x = a·col + b·row + corner.x, y = e·col − a·row + corner.y).
        pub transform: Option<[f64; 3]>,
        /// (model type, EPSG code): (1, code) projected, (2, code) geographic; None: no GeoKeys.
        pub epsg: Option<(u16, u16)>,
        pub pixel_is_point: bool,
        pub nodata: Option<String>,
        pub compression: Compression,
        pub rows_per_strip: u32,
    }

    impl Default for Encoding {
        fn default() -> Self {
            Encoding {
                corner: [1000.0, 5040.0],
                scale: Some([10.0, 10.0]),
                transform: None,
                epsg: Some((1, 2154)),
                pixel_is_point: false,
                nodata: None,
                compression: Compression::Uncompressed,
                rows_per_strip: 2,
            }
        }
    }

    /// Writes `values` (row 0 first, the north row of a north-up raster) as float32.
    pub fn write(path: &Path, width: u32, height: u32, values: &[f32], e: &Encoding) -> tiff::TiffResult<()> {
        let file = std::io::BufWriter::new(std::fs::File::create(path)?);
        let mut encoder = TiffEncoder::new(file)?.with_compression(e.compression);
        let mut image = encoder.new_image::<Gray32Float>(width, height)?;
        image.rows_per_strip(e.rows_per_strip)?;
        let dir = image.encoder();
        if let Some([sx, sy]) = e.scale {
            dir.write_tag(Tag::ModelPixelScaleTag, &[sx, sy, 0.0][..])?;
            dir.write_tag(Tag::ModelTiepointTag, &[0.0, 0.0, 0.0, e.corner[0], e.corner[1], 0.0][..])?;
        }
        if let Some([a, b, c]) = e.transform {
            let m = [a, b, 0.0, e.corner[0], c, -a, 0.0, e.corner[1], 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 1.0];
            dir.write_tag(Tag::ModelTransformationTag, &m[..])?;
        }
        if let Some((model, code)) = e.epsg {
            let raster_type = if e.pixel_is_point { 2 } else { 1 };
            let crs_key = if model == 2 { 2048 } else { 3072 };
            let keys = [1, 1, 0, 3, 1024, 0, 1, model, 1025, 0, 1, raster_type, crs_key, 0, 1, code];
            dir.write_tag(Tag::GeoKeyDirectoryTag, &keys[..])?;
        }
        if let Some(nodata) = &e.nodata {
            dir.write_tag(Tag::GdalNodata, &nodata[..])?;
        }
        image.write_data(values)
    }
}
