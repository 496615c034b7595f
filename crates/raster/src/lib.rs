//! A small RGB canvas for karstgen's pictures: network renders, SDF slices, metric plots and
//! mesh previews. It draws lines, filled rectangles and discs and 8×8-pixel text (the public
//! domain font8x8 glyphs), and writes 8-bit RGB PNG files atomically. Drawing is clipped to the
//! canvas; coordinates are pixels, x to the right, y down.

use std::io::Write;
use std::path::Path;

use font8x8::legacy::BASIC_LEGACY;

/// An RGB colour.
pub type Rgb = [u8; 3];

pub const WHITE: Rgb = [255, 255, 255];
pub const BLACK: Rgb = [0, 0, 0];
pub const GREY: Rgb = [160, 160, 160];

/// A picture being drawn.
#[derive(Debug, Clone, PartialEq)]
pub struct Canvas {
    pub width: u32,
    pub height: u32,
    pixels: Vec<Rgb>,
}

impl Canvas {
    /// A canvas filled with `background`.
    pub fn new(width: u32, height: u32, background: Rgb) -> Self {
        Canvas { width, height, pixels: vec![background; width as usize * height as usize] }
    }

    /// The colour at (x, y), if inside.
    pub fn get(&self, x: i64, y: i64) -> Option<Rgb> {
        self.index(x, y).map(|i| self.pixels[i])
    }

    /// Sets one pixel (ignored outside the canvas).
    pub fn set(&mut self, x: i64, y: i64, colour: Rgb) {
        if let Some(i) = self.index(x, y) {
            self.pixels[i] = colour;
        }
    }

    fn index(&self, x: i64, y: i64) -> Option<usize> {
        let inside = x >= 0 && y >= 0 && x < i64::from(self.width) && y < i64::from(self.height);
        inside.then(|| y as usize * self.width as usize + x as usize)
    }

    /// A line from (x0, y0) to (x1, y1), `thickness` pixels wide.
    pub fn line(&mut self, (x0, y0): (f64, f64), (x1, y1): (f64, f64), thickness: f64, colour: Rgb) {
        let steps = (x1 - x0).abs().max((y1 - y0).abs()).ceil().max(1.0) as usize;
        let radius = (thickness * 0.5).max(0.75);
        for s in 0..=steps {
            let t = s as f64 / steps as f64;
            self.disc((x0 + (x1 - x0) * t, y0 + (y1 - y0) * t), radius, colour);
        }
    }

    /// A filled disc centred at (cx, cy).
    pub fn disc(&mut self, (cx, cy): (f64, f64), radius: f64, colour: Rgb) {
        let r = radius.max(0.75);
        for y in (cy - r).floor() as i64..=(cy + r).ceil() as i64 {
            for x in (cx - r).floor() as i64..=(cx + r).ceil() as i64 {
                let (dx, dy) = (x as f64 + 0.5 - cx, y as f64 + 0.5 - cy);
                if dx * dx + dy * dy <= r * r {
                    self.set(x, y, colour);
                }
            }
        }
    }

    /// A filled axis-aligned rectangle with corners (x0, y0) and (x1, y1).
    pub fn rect(&mut self, (x0, y0): (f64, f64), (x1, y1): (f64, f64), colour: Rgb) {
        let (xa, xb) = (x0.min(x1).round() as i64, x0.max(x1).round() as i64);
        let (ya, yb) = (y0.min(y1).round() as i64, y0.max(y1).round() as i64);
        for y in ya..yb.max(ya + 1) {
            for x in xa..xb.max(xa + 1) {
                self.set(x, y, colour);
            }
        }
    }

    /// Text with its top-left corner at (x, y), `scale` pixels per font pixel; characters
    /// outside Basic Latin are drawn as '?'. Returns the width drawn, in pixels.
    pub fn text(&mut self, (x, y): (i64, i64), text: &str, scale: u32, colour: Rgb) -> i64 {
        let s = i64::from(scale.max(1));
        for (n, ch) in text.chars().enumerate() {
            let code = if ch.is_ascii() { ch as usize } else { '?' as usize };
            let glyph = BASIC_LEGACY[code];
            let left = x + n as i64 * 8 * s;
            for (row, bits) in glyph.iter().enumerate() {
                for col in 0..8 {
                    if bits >> col & 1 == 1 {
                        for dy in 0..s {
                            for dx in 0..s {
                                self.set(left + col * s + dx, y + row as i64 * s + dy, colour);
                            }
                        }
                    }
                }
            }
        }
        text.chars().count() as i64 * 8 * s
    }

    /// Encodes the canvas as an 8-bit RGB PNG.
    pub fn encode_png(&self, out: impl Write) -> Result<(), png::EncodingError> {
        let mut encoder = png::Encoder::new(out, self.width, self.height);
        encoder.set_color(png::ColorType::Rgb);
        encoder.set_depth(png::BitDepth::Eight);
        let mut writer = encoder.write_header()?;
        let bytes: Vec<u8> = self.pixels.iter().flatten().copied().collect();
        writer.write_image_data(&bytes)?;
        writer.finish()
    }

    /// Writes the canvas as a PNG file, atomically (temporary file then rename).
    pub fn write_png(&self, path: &Path) -> std::io::Result<()> {
        let mut bytes = Vec::new();
        self.encode_png(&mut bytes).map_err(std::io::Error::other)?;
        let tmp = path.with_extension(format!("png.tmp-{}", std::process::id()));
        std::fs::write(&tmp, &bytes)?;
        std::fs::rename(&tmp, path)
    }
}

/// Linear map from a data interval onto a pixel interval.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Scale {
    pub from: (f64, f64),
    pub to: (f64, f64),
}

impl Scale {
    /// Maps `v`; a degenerate data interval maps to the middle of the pixel interval.
    pub fn map(&self, v: f64) -> f64 {
        let span = self.from.1 - self.from.0;
        if span.abs() < f64::EPSILON {
            return (self.to.0 + self.to.1) * 0.5;
        }
        self.to.0 + (v - self.from.0) / span * (self.to.1 - self.to.0)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn draws_and_clips() {
        let mut c = Canvas::new(20, 10, WHITE);
        c.line((-5.0, 5.0), (30.0, 5.0), 1.0, BLACK);
        assert_eq!(c.get(0, 5), Some(BLACK));
        assert_eq!(c.get(19, 5), Some(BLACK));
        assert_eq!(c.get(10, 0), Some(WHITE));
        assert_eq!(c.get(20, 5), None);
        c.rect((2.0, 1.0), (4.0, 3.0), GREY);
        assert_eq!(c.get(3, 2), Some(GREY));
    }

    #[test]
    fn text_sets_pixels_of_the_glyph() {
        let mut c = Canvas::new(16, 8, WHITE);
        assert_eq!(c.text((0, 0), "H", 1, BLACK), 8);
        let inked = (0..8)
            .flat_map(|y| (0..8).map(move |x| (x, y)))
            .filter(|&(x, y)| c.get(x, y) == Some(BLACK))
            .count();
        assert!(inked > 10, "{inked}");
        assert!((8..16).all(|x| c.get(x, 4) == Some(WHITE)));
    }

    #[test]
    fn png_round_trip_header() {
        let c = Canvas::new(3, 2, [10, 20, 30]);
        let mut bytes = Vec::new();
        c.encode_png(&mut bytes).unwrap();
        assert_eq!(&bytes[1..4], b"PNG");
    }

    #[test]
    fn scale_maps_linearly_and_survives_degenerate_ranges() {
        let s = Scale { from: (0.0, 10.0), to: (100.0, 200.0) };
        assert_eq!(s.map(5.0), 150.0);
        assert_eq!(Scale { from: (3.0, 3.0), to: (0.0, 10.0) }.map(3.0), 5.0);
    }
}
