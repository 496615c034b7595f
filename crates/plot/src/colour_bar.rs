//! Continuous colour scales and their key: a [`ColourMap`] interpolates colours between stops,
//! a [`ColourBar`] maps a data interval onto it and draws the vertical bar with ticks at nice
//! numbers and a title with the unit.

use crate::canvas::{Canvas, GREY, INK, Rect, Rgb};
use crate::text::{self, Align, SMALL, Valign};
use crate::ticks;

/// Width of the bar itself and the room its ticks, labels and title take, pixels.
pub const BAR_WIDTH: f64 = 16.0;
const TICK: f64 = 4.0;
/// Gap between the title and the bar, room for half the top label.
const TITLE_GAP: f64 = 10.0;

/// Colours at increasing positions in [0, 1], linearly interpolated.
#[derive(Debug, Clone, PartialEq)]
pub struct ColourMap {
    stops: Vec<(f64, Rgb)>,
}

impl ColourMap {
    /// A map through `stops` (positions increasing from 0 to 1; at least one stop).
    pub fn new(stops: &[(f64, Rgb)]) -> ColourMap {
        assert!(!stops.is_empty() && stops.windows(2).all(|w| w[0].0 < w[1].0), "colour stops increase");
        ColourMap { stops: stops.to_vec() }
    }

    /// The colour at `t`, clamped to [0, 1].
    pub fn at(&self, t: f64) -> Rgb {
        let t = if t.is_nan() { 0.0 } else { t.clamp(0.0, 1.0) };
        let i = self.stops.partition_point(|s| s.0 <= t);
        if i == 0 {
            return self.stops[0].1;
        }
        if i == self.stops.len() {
            return self.stops[i - 1].1;
        }
        let ((t0, a), (t1, b)) = (self.stops[i - 1], self.stops[i]);
        let f = (t - t0) / (t1 - t0);
        std::array::from_fn(|k| (f64::from(a[k]) + (f64::from(b[k]) - f64::from(a[k])) * f).round() as u8)
    }
}

/// A colour map over a data interval, with a title (and unit).
#[derive(Debug, Clone, PartialEq)]
pub struct ColourBar {
    pub map: ColourMap,
    /// Data values at the bottom and top of the bar.
    pub range: (f64, f64),
    pub title: String,
}

impl ColourBar {
    /// The colour of data value `v`.
    pub fn colour(&self, v: f64) -> Rgb {
        let (lo, hi) = self.range;
        self.map.at(if hi > lo { (v - lo) / (hi - lo) } else { 0.5 })
    }

    /// The labelled values: nice numbers inside the range.
    pub fn ticks(&self, height: f64) -> Vec<f64> {
        ticks::ticks(self.range.0, self.range.1, (height / 40.0).round().max(2.0) as usize)
    }

    /// Width the bar, its labels and title take.
    pub fn width(&self, height: f64) -> f64 {
        let labels =
            self.labels(height).iter().map(|(_, l)| text::measure(l, SMALL.size).0).fold(0.0, f64::max);
        (BAR_WIDTH + TICK + 3.0 + labels).max(text::measure(&self.title, SMALL.size).0)
    }

    /// Room above the bar for the title.
    pub fn title_height() -> f64 {
        text::measure("M", SMALL.size).1 + TITLE_GAP
    }

    fn labels(&self, height: f64) -> Vec<(f64, String)> {
        let ticks = self.ticks(height);
        let step = if ticks.len() >= 2 { ticks[1] - ticks[0] } else { 1.0 };
        ticks.into_iter().map(|t| (t, ticks::format(t, step))).collect()
    }

    /// Draws the bar in `bar` (low values at the bottom) with ticks on its right and the title
    /// above it.
    pub fn draw(&self, canvas: &mut Canvas, bar: Rect) {
        let rows = bar.height().round().max(1.0) as usize;
        for r in 0..rows {
            let t = 1.0 - (r as f64 + 0.5) / rows as f64;
            let y = bar.y0 + r as f64;
            canvas.fill_rect(Rect { x0: bar.x0, y0: y, x1: bar.x1, y1: y + 1.0 }, self.map.at(t));
        }
        canvas.stroke_rect(bar, 1.0, GREY);
        let (lo, hi) = self.range;
        for (t, label) in self.labels(bar.height()) {
            let y =
                if hi > lo { bar.y1 - (t - lo) / (hi - lo) * bar.height() } else { (bar.y0 + bar.y1) / 2.0 };
            canvas.line((bar.x1, y), (bar.x1 + TICK, y), 1.0, INK);
            text::draw(canvas, &label, (bar.x1 + TICK + 3.0, y), SMALL, Align::Left, Valign::Middle);
        }
        text::draw(canvas, &self.title, (bar.x0, bar.y0 - TITLE_GAP), SMALL, Align::Left, Valign::Bottom);
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::canvas::WHITE;

    fn bar() -> ColourBar {
        ColourBar {
            map: ColourMap::new(&[(0.0, [0, 0, 0]), (0.5, [200, 0, 0]), (1.0, [200, 200, 200])]),
            range: (0.0, 40.0),
            title: "depth into rock (m)".into(),
        }
    }

    #[test]
    fn maps_interpolate_between_stops_and_clamp() {
        let b = bar();
        assert_eq!(b.map.at(0.25), [100, 0, 0]);
        assert_eq!(b.colour(-5.0), [0, 0, 0]);
        assert_eq!(b.colour(40.0), [200, 200, 200]);
        assert_eq!(b.colour(1e9), [200, 200, 200]);
        assert_eq!(b.colour(20.0), [200, 0, 0]);
    }

    #[test]
    fn the_bar_spans_its_range_and_labels_lie_inside_it() {
        let b = bar();
        let ticks = b.ticks(200.0);
        assert_eq!(ticks.first(), Some(&0.0));
        assert_eq!(ticks.last(), Some(&40.0));
        assert!(ticks.iter().all(|t| (0.0..=40.0).contains(t)));
        let mut c = Canvas::new(200, 260, WHITE);
        let r = Rect::at(20.0, 30.0, BAR_WIDTH, 200.0);
        b.draw(&mut c, r);
        // The top row shows the top of the range, the bottom row the bottom.
        assert_eq!(c.get(28, 31), Some(b.colour(40.0 * (1.0 - 1.5 / 200.0))));
        assert_eq!(c.get(28, 228), Some(b.colour(40.0 * 1.5 / 200.0)));
        assert!(b.width(200.0) > BAR_WIDTH + 10.0);
    }
}
