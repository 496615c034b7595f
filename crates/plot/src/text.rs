//! Text: DejaVu Sans (embedded, see fonts/README.md) laid out with its advances and kerning,
//! each glyph's outline turned into a path and filled anti-aliased, at any size and angle. An
//! optional halo (the outline stroked in the background colour first) keeps labels readable
//! over lines. No system font, fontconfig or FreeType is involved, so every machine draws the
//! same pixels.

use std::sync::OnceLock;

use ab_glyph::{Font, FontRef, OutlineCurve};
use tiny_skia::{PathBuilder, Transform};

use crate::canvas::{Canvas, INK, Point, Rect, Rgb, WHITE};

const DEJAVU_SANS: &[u8] = include_bytes!("../fonts/DejaVuSans.ttf");

fn font() -> &'static FontRef<'static> {
    static FONT: OnceLock<FontRef<'static>> = OnceLock::new();
    FONT.get_or_init(|| FontRef::try_from_slice(DEJAVU_SANS).expect("the embedded DejaVu Sans parses"))
}

/// Horizontal placement of the text relative to its anchor point.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Align {
    Left,
    Centre,
    Right,
}

/// Vertical placement of the text box (ascent to descent) relative to its anchor point.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Valign {
    Top,
    Middle,
    Bottom,
}

/// How text looks: size in pixels (the em), colour, and a halo colour drawn around the glyphs.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Style {
    pub size: f64,
    pub colour: Rgb,
    pub halo: Option<Rgb>,
}

impl Style {
    /// Dark text of `size` pixels, no halo.
    pub const fn new(size: f64) -> Style {
        Style { size, colour: INK, halo: None }
    }

    pub const fn colour(self, colour: Rgb) -> Style {
        Style { colour, ..self }
    }

    /// With a white halo, for labels drawn over a picture.
    pub const fn halo(self) -> Style {
        Style { halo: Some(WHITE), ..self }
    }
}

/// Tick labels, legend entries, notes.
pub const SMALL: Style = Style::new(12.0);
/// Axis titles.
pub const NORMAL: Style = Style::new(14.0);
/// Picture titles.
pub const TITLE: Style = Style::new(18.0);

/// Width and height (ascent to descent) of `text` at `size` pixels.
pub fn measure(text: &str, size: f64) -> (f64, f64) {
    let f = font();
    let s = scale(size);
    (advance(text) * s, f64::from(f.ascent_unscaled() - f.descent_unscaled()) * s)
}

/// Draws `text` anchored at `at`, horizontal; returns its box.
pub fn draw(canvas: &mut Canvas, text: &str, at: Point, style: Style, align: Align, valign: Valign) -> Rect {
    draw_rotated(canvas, text, at, style, (align, valign), 0.0);
    text_box(text, at, style.size, align, valign)
}

/// The box `draw` would fill, without drawing.
pub fn text_box(text: &str, (x, y): Point, size: f64, align: Align, valign: Valign) -> Rect {
    let (w, h) = measure(text, size);
    let (dx, baseline) = offsets(text, size, align, valign);
    let top = y + baseline - ascent(size);
    Rect::at(x - dx, top, w, h)
}

/// Draws `text` anchored at `at`, turned by `degrees` clockwise (−90: reading upwards).
pub fn draw_rotated(
    canvas: &mut Canvas,
    text: &str,
    at: Point,
    style: Style,
    anchor: (Align, Valign),
    degrees: f64,
) {
    let Some(path) = outline(text) else { return };
    let s = scale(style.size);
    let (dx, baseline) = offsets(text, style.size, anchor.0, anchor.1);
    let transform = Transform::from_scale(s as f32, -s as f32)
        .post_translate(-dx as f32, baseline as f32)
        .post_rotate(degrees as f32)
        .post_translate(at.0 as f32, at.1 as f32);
    if let Some(halo) = style.halo {
        canvas.stroke_path(&path, transform, (style.size * 0.25).max(2.0) / s, halo);
    }
    canvas.fill_path(&path, transform, style.colour);
}

/// `text` broken between words into lines at most `max_width` pixels wide at `size` (a single
/// word wider than that keeps its own line).
pub fn wrap(text: &str, size: f64, max_width: f64) -> Vec<String> {
    let mut lines: Vec<String> = Vec::new();
    for word in text.split_whitespace() {
        match lines.last_mut() {
            Some(line) if measure(&format!("{line} {word}"), size).0 <= max_width => {
                line.push(' ');
                line.push_str(word);
            }
            _ => lines.push(word.to_string()),
        }
    }
    lines
}

/// Pixels per font unit at `size`.
fn scale(size: f64) -> f64 {
    let f = font();
    size / f64::from(f.units_per_em().unwrap_or(2048.0))
}

fn ascent(size: f64) -> f64 {
    f64::from(font().ascent_unscaled()) * scale(size)
}

/// The anchor's offset from the text's left end, and the baseline's offset from the anchor
/// (y down), in pixels.
fn offsets(text: &str, size: f64, align: Align, valign: Valign) -> (f64, f64) {
    let (w, h) = measure(text, size);
    let dx = match align {
        Align::Left => 0.0,
        Align::Centre => w / 2.0,
        Align::Right => w,
    };
    let top_to_baseline = ascent(size);
    let baseline = match valign {
        Valign::Top => top_to_baseline,
        Valign::Middle => top_to_baseline - h / 2.0,
        Valign::Bottom => top_to_baseline - h,
    };
    (dx, baseline)
}

/// Advance width of `text`, font units, kerning included.
fn advance(text: &str) -> f64 {
    let f = font();
    let mut width = 0.0;
    let mut previous = None;
    for c in text.chars() {
        let id = f.glyph_id(c);
        if let Some(p) = previous {
            width += f64::from(f.kern_unscaled(p, id));
        }
        width += f64::from(f.h_advance_unscaled(id));
        previous = Some(id);
    }
    width
}

/// The outlines of `text`'s glyphs as one path in font units, y up, the pen starting at 0.
fn outline(text: &str) -> Option<tiny_skia::Path> {
    let f = font();
    let mut pb = PathBuilder::new();
    let mut pen = 0.0f32;
    let mut previous = None;
    for c in text.chars() {
        let id = f.glyph_id(c);
        if let Some(p) = previous {
            pen += f.kern_unscaled(p, id);
        }
        if let Some(glyph) = f.outline(id) {
            add_curves(&mut pb, &glyph.curves, pen);
        }
        pen += f.h_advance_unscaled(id);
        previous = Some(id);
    }
    pb.finish()
}

/// Appends a glyph's curves shifted right by `dx`, starting a contour wherever a curve does not
/// begin at the previous curve's end.
fn add_curves(pb: &mut PathBuilder, curves: &[OutlineCurve], dx: f32) {
    let mut end: Option<ab_glyph::Point> = None;
    for curve in curves {
        let (start, last) = match curve {
            OutlineCurve::Line(a, b) => (*a, *b),
            OutlineCurve::Quad(a, _, b) => (*a, *b),
            OutlineCurve::Cubic(a, _, _, b) => (*a, *b),
        };
        if end != Some(start) {
            if end.is_some() {
                pb.close();
            }
            pb.move_to(start.x + dx, start.y);
        }
        match curve {
            OutlineCurve::Line(_, b) => pb.line_to(b.x + dx, b.y),
            OutlineCurve::Quad(_, c, b) => pb.quad_to(c.x + dx, c.y, b.x + dx, b.y),
            OutlineCurve::Cubic(_, c1, c2, b) => pb.cubic_to(c1.x + dx, c1.y, c2.x + dx, c2.y, b.x + dx, b.y),
        }
        end = Some(last);
    }
    if end.is_some() {
        pb.close();
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn measures_grow_with_text_and_size() {
        let (w1, h1) = measure("sink", 12.0);
        let (w2, _) = measure("sink-01", 12.0);
        let (w3, h3) = measure("sink", 24.0);
        assert!(w1 > 12.0 && w2 > w1, "{w1} {w2}");
        assert!((w3 - 2.0 * w1).abs() < 1e-9 && (h3 - 2.0 * h1).abs() < 1e-9);
        assert!(h1 > 12.0 && h1 < 16.0, "{h1}");
    }

    #[test]
    fn glyphs_ink_their_box_and_nothing_outside() {
        let mut c = Canvas::new(120, 40, WHITE);
        let b = draw(
            &mut c,
            "Hx 10 m",
            (10.0, 10.0),
            Style::new(16.0).colour([0, 0, 0]),
            Align::Left,
            Valign::Top,
        );
        let inked: Vec<(i64, i64)> = (0..40)
            .flat_map(|y| (0..120).map(move |x| (x, y)))
            .filter(|&(x, y)| c.get(x, y) != Some(WHITE))
            .collect();
        assert!(inked.len() > 60, "{}", inked.len());
        let grown = b.inflate(1.0);
        assert!(inked.iter().all(|&(x, y)| x as f64 >= grown.x0
            && (x as f64) < grown.x1
            && y as f64 >= grown.y0
            && (y as f64) < grown.y1));
        // Some pixel is fully black: glyph stems are filled, not just edges.
        assert!(inked.iter().any(|&(x, y)| c.get(x, y) == Some([0, 0, 0])));
    }

    #[test]
    fn wrapped_lines_fit_and_keep_every_word() {
        let text = "not labelled in the side view: sink-01, sink-02, waypoint-13, waypoint-14";
        let lines = wrap(text, 12.0, 150.0);
        assert!(lines.len() >= 3);
        assert!(lines.iter().all(|l| measure(l, 12.0).0 <= 150.0));
        assert_eq!(lines.join(" "), text);
    }

    #[test]
    fn anchors_place_the_box() {
        let at = (50.0, 20.0);
        let centre = text_box("abc", at, 12.0, Align::Centre, Valign::Middle);
        assert!(((centre.x0 + centre.x1) / 2.0 - at.0).abs() < 1e-9);
        assert!(((centre.y0 + centre.y1) / 2.0 - at.1).abs() < 1e-9);
        let right = text_box("abc", at, 12.0, Align::Right, Valign::Bottom);
        assert!((right.x1 - at.0).abs() < 1e-9 && (right.y1 - at.1).abs() < 1e-9);
    }
}
