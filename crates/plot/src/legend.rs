//! Legends: a swatch (line, patch or dot) and a label per entry, laid out left to right and
//! wrapped to a width (under a picture) or one per row (in a side panel).

use crate::canvas::{Canvas, GREY, Point, Rect, Rgb};
use crate::text::{self, Align, SMALL, Valign};

/// Pixels: swatch width, gap swatch–label, gap between entries, row height.
const SWATCH: f64 = 22.0;
const GAP: f64 = 6.0;
const SPACING: f64 = 18.0;
const ROW: f64 = 19.0;

/// What an entry's colour stands for.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Swatch {
    /// A line of this width, pixels.
    Line(Rgb, f64),
    /// A filled square with a grey outline.
    Patch(Rgb),
    /// A dot with a white rim (a key point).
    Dot(Rgb),
}

/// One legend entry.
#[derive(Debug, Clone, PartialEq)]
pub struct Entry {
    pub swatch: Swatch,
    pub label: String,
}

impl Entry {
    pub fn new(swatch: Swatch, label: impl Into<String>) -> Entry {
        Entry { swatch, label: label.into() }
    }

    fn width(&self) -> f64 {
        SWATCH + GAP + text::measure(&self.label, SMALL.size).0
    }
}

/// Where each entry goes when flowed into rows `max_width` wide from `at`.
fn flow(entries: &[Entry], at: Point, max_width: f64) -> Vec<Point> {
    let (mut x, mut y) = at;
    entries
        .iter()
        .map(|e| {
            let w = e.width();
            if x > at.0 && x + w > at.0 + max_width {
                (x, y) = (at.0, y + ROW);
            }
            let here = (x, y);
            x += w + SPACING;
            here
        })
        .collect()
}

/// Height of the legend flowed into rows `max_width` wide (0 when empty).
pub fn flowed_height(entries: &[Entry], max_width: f64) -> f64 {
    flow(entries, (0.0, 0.0), max_width).last().map_or(0.0, |p| p.1 + ROW)
}

/// Draws the entries in rows `max_width` wide from `at` (top-left); returns the bottom.
pub fn draw_flowed(canvas: &mut Canvas, entries: &[Entry], at: Point, max_width: f64) -> f64 {
    for (e, p) in entries.iter().zip(flow(entries, at, max_width)) {
        draw_entry(canvas, e, p);
    }
    at.1 + flowed_height(entries, max_width)
}

/// Size of the legend drawn one entry per row.
pub fn column_size(entries: &[Entry]) -> (f64, f64) {
    (entries.iter().map(Entry::width).fold(0.0, f64::max), ROW * entries.len() as f64)
}

/// Draws one entry per row from `at` (top-left); returns the bottom.
pub fn draw_column(canvas: &mut Canvas, entries: &[Entry], at: Point) -> f64 {
    for (i, e) in entries.iter().enumerate() {
        draw_entry(canvas, e, (at.0, at.1 + ROW * i as f64));
    }
    at.1 + ROW * entries.len() as f64
}

fn draw_entry(canvas: &mut Canvas, entry: &Entry, (x, y): Point) {
    let mid = y + ROW / 2.0;
    match entry.swatch {
        Swatch::Line(rgb, width) => canvas.line((x + 2.0, mid), (x + SWATCH - 2.0, mid), width, rgb),
        Swatch::Patch(rgb) => {
            let r = Rect::at(x + 4.0, mid - 6.0, SWATCH - 8.0, 12.0);
            canvas.fill_rect(r, rgb);
            canvas.stroke_rect(r, 1.0, GREY);
        }
        Swatch::Dot(rgb) => {
            canvas.disc((x + SWATCH / 2.0, mid), 5.0, [255, 255, 255]);
            canvas.disc((x + SWATCH / 2.0, mid), 3.5, rgb);
        }
    }
    text::draw(canvas, &entry.label, (x + SWATCH + GAP, mid), SMALL, Align::Left, Valign::Middle);
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::canvas::WHITE;

    fn entries(n: usize) -> Vec<Entry> {
        (0..n).map(|i| Entry::new(Swatch::Patch([200, 0, 0]), format!("type {i}"))).collect()
    }

    #[test]
    fn flowed_entries_wrap_within_the_width_and_do_not_overlap() {
        let es = entries(12);
        let at = flow(&es, (10.0, 5.0), 300.0);
        for (e, p) in es.iter().zip(&at) {
            assert!(p.0 + e.width() <= 310.0 + 1e-9 || p.0 == 10.0);
        }
        let boxes: Vec<Rect> = es.iter().zip(&at).map(|(e, p)| Rect::at(p.0, p.1, e.width(), ROW)).collect();
        for (i, a) in boxes.iter().enumerate() {
            assert!(boxes[i + 1..].iter().all(|b| !a.overlaps(b)));
        }
        assert!(flowed_height(&es, 300.0) >= 3.0 * ROW);
        assert_eq!(flowed_height(&[], 300.0), 0.0);
    }

    #[test]
    fn swatches_show_their_colour() {
        let mut c = Canvas::new(200, 60, WHITE);
        let bottom = draw_column(&mut c, &entries(2), (0.0, 0.0));
        assert_eq!(bottom, 2.0 * ROW);
        assert_eq!(c.get(11, (ROW / 2.0) as i64), Some([200, 0, 0]));
    }
}
