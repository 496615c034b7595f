//! The picture being drawn: an RGB canvas with anti-aliased shapes (tiny-skia) and single-pixel
//! access for rasters (slices, software renders), written as an 8-bit RGB PNG. Coordinates are
//! pixels, x to the right, y down; drawing is clipped to the canvas.

use std::io::Write;
use std::path::Path;

use tiny_skia::{
    FillRule, LineCap, LineJoin, Paint, PathBuilder, Pixmap, PremultipliedColorU8, Stroke, Transform,
};

/// An RGB colour.
pub type Rgb = [u8; 3];

pub const WHITE: Rgb = [255, 255, 255];
pub const BLACK: Rgb = [0, 0, 0];
pub const GREY: Rgb = [150, 150, 150];
pub const LIGHT_GREY: Rgb = [225, 225, 225];
/// Dark grey for text and frames that should not shout.
pub const INK: Rgb = [40, 40, 40];

/// A point in pixels.
pub type Point = (f64, f64);

/// An axis-aligned rectangle in pixels, `x0 ≤ x1`, `y0 ≤ y1`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Rect {
    pub x0: f64,
    pub y0: f64,
    pub x1: f64,
    pub y1: f64,
}

impl Rect {
    /// The rectangle with top-left corner `(x, y)` and size `w` × `h`.
    pub fn at(x: f64, y: f64, w: f64, h: f64) -> Rect {
        Rect { x0: x, y0: y, x1: x + w, y1: y + h }
    }

    pub fn width(&self) -> f64 {
        self.x1 - self.x0
    }

    pub fn height(&self) -> f64 {
        self.y1 - self.y0
    }

    /// Whether the interiors intersect (touching edges do not overlap).
    pub fn overlaps(&self, other: &Rect) -> bool {
        self.x0 < other.x1 && other.x0 < self.x1 && self.y0 < other.y1 && other.y0 < self.y1
    }

    /// Whether `other` lies entirely inside.
    pub fn contains(&self, other: &Rect) -> bool {
        other.x0 >= self.x0 && other.x1 <= self.x1 && other.y0 >= self.y0 && other.y1 <= self.y1
    }

    /// Grown by `d` on every side.
    pub fn inflate(&self, d: f64) -> Rect {
        Rect { x0: self.x0 - d, y0: self.y0 - d, x1: self.x1 + d, y1: self.y1 + d }
    }

    /// The point of the rectangle nearest to `p`.
    pub fn nearest(&self, (x, y): Point) -> Point {
        (x.clamp(self.x0, self.x1), y.clamp(self.y0, self.y1))
    }
}

/// A picture being drawn.
#[derive(Clone, PartialEq)]
pub struct Canvas {
    pixmap: Pixmap,
}

impl std::fmt::Debug for Canvas {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "Canvas({} × {})", self.width(), self.height())
    }
}

impl Canvas {
    /// A canvas filled with `background`; each side is clamped to 1..=16384 pixels.
    pub fn new(width: u32, height: u32, background: Rgb) -> Self {
        let side = |s: u32| s.clamp(1, 16384);
        let mut pixmap = Pixmap::new(side(width), side(height)).expect("a canvas of 1..=16384 pixels a side");
        pixmap.fill(colour(background));
        Canvas { pixmap }
    }

    pub fn width(&self) -> u32 {
        self.pixmap.width()
    }

    pub fn height(&self) -> u32 {
        self.pixmap.height()
    }

    /// The whole canvas as a rectangle.
    pub fn bounds(&self) -> Rect {
        Rect::at(0.0, 0.0, f64::from(self.width()), f64::from(self.height()))
    }

    /// The colour at pixel (x, y), if inside.
    pub fn get(&self, x: i64, y: i64) -> Option<Rgb> {
        let (x, y) = (u32::try_from(x).ok()?, u32::try_from(y).ok()?);
        if x >= self.width() {
            return None;
        }
        self.pixmap.pixel(x, y).map(|p| {
            let c = p.demultiply();
            [c.red(), c.green(), c.blue()]
        })
    }

    /// Sets one pixel, opaque (ignored outside the canvas).
    pub fn set(&mut self, x: i64, y: i64, rgb: Rgb) {
        let (w, h) = (i64::from(self.width()), i64::from(self.height()));
        if (0..w).contains(&x) && (0..h).contains(&y) {
            let opaque = PremultipliedColorU8::from_rgba(rgb[0], rgb[1], rgb[2], 255).expect("opaque");
            self.pixmap.pixels_mut()[(y * w + x) as usize] = opaque;
        }
    }

    /// A straight line `width` pixels wide with round ends.
    pub fn line(&mut self, a: Point, b: Point, width: f64, rgb: Rgb) {
        self.polyline(&[a, b], width, rgb);
    }

    /// A connected line through `points`, `width` pixels wide, round ends and joins.
    pub fn polyline(&mut self, points: &[Point], width: f64, rgb: Rgb) {
        let Some(path) = path(points, false) else { return };
        let stroke = Stroke {
            width: width as f32,
            line_cap: LineCap::Round,
            line_join: LineJoin::Round,
            ..Stroke::default()
        };
        self.pixmap.stroke_path(&path, &paint(rgb), &stroke, Transform::identity(), None);
    }

    /// A filled rectangle (not anti-aliased, so that adjacent cells tile without seams).
    pub fn fill_rect(&mut self, r: Rect, rgb: Rgb) {
        if let Some(rect) = tiny_skia::Rect::from_ltrb(r.x0 as f32, r.y0 as f32, r.x1 as f32, r.y1 as f32) {
            let mut p = paint(rgb);
            p.anti_alias = false;
            self.pixmap.fill_rect(rect, &p, Transform::identity(), None);
        }
    }

    /// The outline of a rectangle, `width` pixels wide.
    pub fn stroke_rect(&mut self, r: Rect, width: f64, rgb: Rgb) {
        let corners = [(r.x0, r.y0), (r.x1, r.y0), (r.x1, r.y1), (r.x0, r.y1)];
        if let Some(path) = path(&corners, true) {
            let stroke = Stroke { width: width as f32, line_join: LineJoin::Miter, ..Stroke::default() };
            self.pixmap.stroke_path(&path, &paint(rgb), &stroke, Transform::identity(), None);
        }
    }

    /// A filled disc.
    pub fn disc(&mut self, (cx, cy): Point, radius: f64, rgb: Rgb) {
        if let Some(path) = PathBuilder::from_circle(cx as f32, cy as f32, radius.max(0.5) as f32) {
            self.pixmap.fill_path(&path, &paint(rgb), FillRule::Winding, Transform::identity(), None);
        }
    }

    /// A circle outline, `width` pixels wide.
    pub fn circle(&mut self, (cx, cy): Point, radius: f64, width: f64, rgb: Rgb) {
        if let Some(path) = PathBuilder::from_circle(cx as f32, cy as f32, radius.max(0.5) as f32) {
            let stroke = Stroke { width: width as f32, ..Stroke::default() };
            self.pixmap.stroke_path(&path, &paint(rgb), &stroke, Transform::identity(), None);
        }
    }

    /// A filled polygon (non-zero winding).
    pub fn fill_polygon(&mut self, points: &[Point], rgb: Rgb) {
        if let Some(path) = path(points, true) {
            self.pixmap.fill_path(&path, &paint(rgb), FillRule::Winding, Transform::identity(), None);
        }
    }

    /// Fills `path` (built in pixels) with `rgb`; used by the text module.
    pub(crate) fn fill_path(&mut self, path: &tiny_skia::Path, transform: Transform, rgb: Rgb) {
        self.pixmap.fill_path(path, &paint(rgb), FillRule::Winding, transform, None);
    }

    /// Strokes `path` with round joins; used by the text module for halos.
    pub(crate) fn stroke_path(&mut self, path: &tiny_skia::Path, transform: Transform, width: f64, rgb: Rgb) {
        let stroke = Stroke { width: width as f32, line_join: LineJoin::Round, ..Stroke::default() };
        self.pixmap.stroke_path(path, &paint(rgb), &stroke, transform, None);
    }

    /// Whether every pixel has the same colour.
    pub fn is_blank(&self) -> bool {
        let pixels = self.pixmap.pixels();
        pixels.iter().all(|p| *p == pixels[0])
    }

    /// Encodes the canvas as an 8-bit RGB PNG (the canvas is opaque: its background is).
    pub fn encode_png(&self, out: impl Write) -> Result<(), png::EncodingError> {
        let mut encoder = png::Encoder::new(out, self.width(), self.height());
        encoder.set_color(png::ColorType::Rgb);
        encoder.set_depth(png::BitDepth::Eight);
        let mut writer = encoder.write_header()?;
        let bytes: Vec<u8> = self
            .pixmap
            .pixels()
            .iter()
            .flat_map(|p| {
                let c = p.demultiply();
                [c.red(), c.green(), c.blue()]
            })
            .collect();
        writer.write_image_data(&bytes)?;
        writer.finish()
    }

    /// Writes the canvas as a PNG file, atomically.
    pub fn write_png(&self, path: &Path) -> std::io::Result<()> {
        let mut bytes = Vec::new();
        self.encode_png(&mut bytes).map_err(std::io::Error::other)?;
        karst_artifact::atomic::write_bytes(path, &bytes)
    }
}

fn colour(rgb: Rgb) -> tiny_skia::Color {
    tiny_skia::Color::from_rgba8(rgb[0], rgb[1], rgb[2], 255)
}

fn paint(rgb: Rgb) -> Paint<'static> {
    let mut p = Paint::default();
    p.set_color(colour(rgb));
    p.anti_alias = true;
    p
}

/// The path through `points`, closed when `close`; a single point makes a zero-length line
/// (drawn as a dot by round caps).
fn path(points: &[Point], close: bool) -> Option<tiny_skia::Path> {
    let (first, rest) = points.split_first()?;
    let mut pb = PathBuilder::new();
    pb.move_to(first.0 as f32, first.1 as f32);
    for p in rest {
        pb.line_to(p.0 as f32, p.1 as f32);
    }
    if rest.is_empty() {
        pb.line_to(first.0 as f32, first.1 as f32);
    }
    if close {
        pb.close();
    }
    pb.finish()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn draws_clips_and_reads_back() {
        let mut c = Canvas::new(20, 10, WHITE);
        assert!(c.is_blank());
        c.line((-5.0, 5.0), (30.0, 5.0), 2.0, BLACK);
        assert_eq!(c.get(0, 5), Some(BLACK));
        assert_eq!(c.get(19, 4), Some(BLACK));
        assert_eq!(c.get(10, 0), Some(WHITE));
        assert_eq!(c.get(20, 5), None);
        c.fill_rect(Rect::at(2.0, 1.0, 2.0, 2.0), GREY);
        assert_eq!(c.get(3, 2), Some(GREY));
        c.set(0, 0, [1, 2, 3]);
        assert_eq!(c.get(0, 0), Some([1, 2, 3]));
        assert!(!c.is_blank());
    }

    #[test]
    fn png_is_rgb_of_the_canvas_size() {
        let c = Canvas::new(3, 2, [10, 20, 30]);
        let mut bytes = Vec::new();
        c.encode_png(&mut bytes).unwrap();
        let decoder = png::Decoder::new(std::io::Cursor::new(bytes));
        let reader = decoder.read_info().unwrap();
        let info = reader.info();
        assert_eq!((info.width, info.height, info.color_type), (3, 2, png::ColorType::Rgb));
    }

    #[test]
    fn rectangles_overlap_only_through_their_interiors() {
        let a = Rect::at(0.0, 0.0, 10.0, 10.0);
        assert!(a.overlaps(&Rect::at(5.0, 5.0, 10.0, 10.0)));
        assert!(!a.overlaps(&Rect::at(10.0, 0.0, 10.0, 10.0)));
        assert!(a.contains(&Rect::at(1.0, 1.0, 2.0, 2.0)));
        assert_eq!(a.nearest((20.0, 5.0)), (10.0, 5.0));
    }
}
