//! Heightfield images: the pixel values of a grayscale PNG (8 or 16 bits) or of one channel of
//! an OpenEXR image, as a grid of numbers in image order (row 0 is the top, the north edge).
//!
//! Only the pixels are read here; what they mean (cell size, origin, vertical scale, offset,
//! no-data value) is the heightfield's, in `karst-geology`. Images of more than [`MAX_PIXELS`]
//! are refused before their pixels are allocated.

use std::path::Path;

/// Most pixels of a heightfield image (16384 × 16384): its elevations take 8 bytes each.
pub const MAX_PIXELS: u64 = 1 << 28;

/// The pixel values of one image channel.
#[derive(Debug, Clone, PartialEq)]
pub struct Image {
    /// Pixels per row.
    pub width: usize,
    /// Rows.
    pub height: usize,
    /// Values, row 0 (the top) first, left to right within a row; an EXR channel keeps its
    /// non-finite values.
    pub values: Vec<f64>,
}

/// Why an image cannot be read; the caller names the file.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum ImageError {
    /// Not a readable PNG or EXR file, or too large.
    #[error("{0}")]
    Unreadable(String),
    /// A readable image of a kind a heightfield cannot be: colour, other bit depths, no channel.
    #[error("{0}")]
    Content(String),
}

/// Decodes the bytes of an 8- or 16-bit grayscale PNG.
pub fn decode_png(bytes: &[u8]) -> Result<Image, ImageError> {
    let unreadable = |e: &dyn std::fmt::Display| ImageError::Unreadable(e.to_string());
    let decoder = png::Decoder::new(std::io::Cursor::new(bytes));
    let mut reader = decoder.read_info().map_err(|e| unreadable(&e))?;
    let (width, height) = (u64::from(reader.info().width), u64::from(reader.info().height));
    if width * height > MAX_PIXELS {
        return Err(ImageError::Unreadable(format!(
            "{width} × {height} pixels, more than the {MAX_PIXELS} a heightfield may have"
        )));
    }
    let size = reader.output_buffer_size().ok_or_else(|| unreadable(&"image too large"))?;
    let mut buffer = vec![0u8; size];
    let info = reader.next_frame(&mut buffer).map_err(|e| unreadable(&e))?;
    if info.color_type != png::ColorType::Grayscale {
        return Err(ImageError::Content(format!("must be a grayscale PNG, found {:?}", info.color_type)));
    }
    let bytes_per_pixel = match info.bit_depth {
        png::BitDepth::Sixteen => 2,
        png::BitDepth::Eight => 1,
        depth => {
            return Err(ImageError::Content(format!("must have 8 or 16 bits per pixel, found {depth:?}")));
        }
    };
    let (w, h) = (info.width as usize, info.height as usize);
    let mut values = Vec::with_capacity(w * h);
    for row in 0..h {
        let line = &buffer[row * info.line_size..][..w * bytes_per_pixel];
        values.extend(line.chunks_exact(bytes_per_pixel).map(|p| match p {
            [hi, lo] => f64::from(u16::from_be_bytes([*hi, *lo])),
            [v] => f64::from(*v),
            _ => unreachable!("chunks of one or two bytes"),
        }));
    }
    Ok(Image { width: w, height: h, values })
}

/// Reads the first layer of an OpenEXR file: its `Y` channel, else `Z`, else `R`, else its first
/// channel, as f32 values.
pub fn read_exr(path: &Path) -> Result<Image, ImageError> {
    let unreadable = |e: &dyn std::fmt::Display| ImageError::Unreadable(e.to_string());
    karst_artifact::files::open_regular(path, karst_artifact::files::MAX_DATA_BYTES)
        .map_err(|e| unreadable(&e))?;
    let image = exr::prelude::read_first_flat_layer_from_file(path).map_err(|e| unreadable(&e))?;
    let layer = &image.layer_data;
    let channels = &layer.channel_data.list;
    let pick = ["Y", "Z", "R"]
        .iter()
        .find_map(|name| channels.iter().find(|c| c.name.to_string() == *name))
        .or(channels.first())
        .ok_or_else(|| ImageError::Content("has no channel".into()))?;
    let (width, height) = (layer.size.width(), layer.size.height());
    let values = pick.sample_data.values_as_f32().map(f64::from).collect();
    Ok(Image { width, height, values })
}

/// Writes `values` (row 0 first, `width` per row) as a 16-bit grayscale PNG.
pub fn write_png16(path: &Path, width: u32, height: u32, values: &[u16]) -> std::io::Result<()> {
    let data: Vec<u8> = values.iter().flat_map(|v| v.to_be_bytes()).collect();
    let file = std::io::BufWriter::new(std::fs::File::create(path)?);
    let mut encoder = png::Encoder::new(file, width, height);
    encoder.set_color(png::ColorType::Grayscale);
    encoder.set_depth(png::BitDepth::Sixteen);
    let mut writer = encoder.write_header().map_err(std::io::Error::other)?;
    writer.write_image_data(&data).map_err(std::io::Error::other)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_16_bit_png_reads_back_row_0_first() {
        let dir = karst_testkit::scratch("geodata-image-png");
        let path = dir.join("h.png");
        write_png16(&path, 3, 2, &[0, 1, 2, 300, 65535, 7]).unwrap();
        let image = decode_png(&std::fs::read(&path).unwrap()).unwrap();
        assert_eq!((image.width, image.height), (3, 2));
        assert_eq!(image.values, [0.0, 1.0, 2.0, 300.0, 65535.0, 7.0]);
    }

    #[test]
    fn colour_and_garbage_are_refused() {
        let mut rgb = Vec::new();
        let mut encoder = png::Encoder::new(&mut rgb, 1, 1);
        encoder.set_color(png::ColorType::Rgb);
        encoder.write_header().unwrap().write_image_data(&[1, 2, 3]).unwrap();
        let err = decode_png(&rgb).unwrap_err();
        assert_eq!(err, ImageError::Content("must be a grayscale PNG, found Rgb".into()));
        assert!(matches!(decode_png(b"not a png"), Err(ImageError::Unreadable(_))));
    }

    #[test]
    fn an_exr_gives_its_r_channel_when_it_has_no_y_or_z() {
        let dir = karst_testkit::scratch("geodata-image-exr");
        let path = dir.join("h.exr");
        exr::prelude::write_rgba_file(&path, 2, 2, |x, y| ((x + 10 * y) as f32, -1.0, -1.0, 1.0)).unwrap();
        let image = read_exr(&path).unwrap();
        assert_eq!((image.width, image.height), (2, 2));
        assert_eq!(image.values, [0.0, 1.0, 10.0, 11.0]);
        assert!(matches!(read_exr(&dir.join("none.exr")), Err(ImageError::Unreadable(_))));
    }
}
