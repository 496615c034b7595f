//! `report.png`: one row per metric, its real-cave range as a grey band, the target cave's value
//! (black bar), the scene's before calibration (orange) and after (blue), each row on its own
//! scale (the band and the three values, padded).

use karst_metrics::ranges::{CHARACTERIZE_KEYS, CaveRange, real_cave_ranges};
use karst_plot::axes::Axes;
use karst_plot::legend::{self, Entry, Swatch};
use karst_plot::text::{self, Align, NORMAL, SMALL, TITLE, Valign};
use karst_plot::{Canvas, GREY, INK, LIGHT_GREY, Rect, Rgb, WHITE, ticks};

use super::evaluate::MetricVector;

pub const BEFORE: Rgb = [230, 120, 20];
pub const AFTER: Rgb = [40, 90, 200];
const BAND: Rgb = [200, 200, 200];
const WIDTH: u32 = 900;
const TOP: f64 = 100.0;
const ROW: f64 = 46.0;
const BAND_FROM: f64 = 230.0;
const BAND_TO: f64 = 640.0;

/// The chart of the target's, the before's and the after's metrics.
pub fn draw(title: &str, target: &MetricVector, before: &MetricVector, after: &MetricVector) -> Canvas {
    let height = (TOP + ROW * CHARACTERIZE_KEYS.len() as f64 + 12.0) as u32;
    let mut c = Canvas::new(WIDTH, height, WHITE);
    text::draw(&mut c, title, (16.0, 12.0), TITLE, Align::Left, Valign::Top);
    let key = [
        Entry::new(Swatch::Patch(BAND), "range of the real caves"),
        Entry::new(Swatch::Line(INK, 3.0), "target cave"),
        Entry::new(Swatch::Dot(BEFORE), "before"),
        Entry::new(Swatch::Dot(AFTER), "after (median over the seeds)"),
    ];
    legend::draw_flowed(&mut c, &key, (16.0, 44.0), WIDTH as f64 - 32.0);
    text::draw(
        &mut c,
        "target / before / after",
        (BAND_TO + 24.0, TOP - 18.0),
        SMALL.colour(GREY),
        Align::Left,
        Valign::Middle,
    );
    let ranges = real_cave_ranges();
    for (i, key) in CHARACTERIZE_KEYS.iter().enumerate() {
        let y = TOP + ROW * i as f64 + ROW / 2.0 - 6.0;
        if i > 0 {
            c.line((16.0, y - ROW / 2.0), (WIDTH as f64 - 16.0, y - ROW / 2.0), 1.0, LIGHT_GREY);
        }
        row(&mut c, key, &ranges[*key], [target[i], before[i], after[i]], y);
    }
    c
}

fn row(c: &mut Canvas, key: &str, range: &CaveRange, [target, before, after]: [f64; 3], y: f64) {
    let finite = [target, before, after].into_iter().filter(|v| v.is_finite());
    let (lo, hi) = finite.fold((range.min, range.max), |(lo, hi), v| (lo.min(v), hi.max(v)));
    let pad = (hi - lo) * 0.08;
    let axes = Axes::new(
        Rect { x0: BAND_FROM, y0: y - 7.0, x1: BAND_TO, y1: y + 7.0 },
        (lo - pad, hi + pad),
        (0.0, 1.0),
    );
    text::draw(c, key, (16.0, y), NORMAL, Align::Left, Valign::Middle);
    c.fill_rect(Rect { x0: axes.px(range.min), y0: y - 7.0, x1: axes.px(range.max), y1: y + 7.0 }, BAND);
    let grey = SMALL.colour(GREY);
    text::draw(c, &ticks::human(range.min), (axes.px(range.min), y + 9.0), grey, Align::Centre, Valign::Top);
    text::draw(c, &ticks::human(range.max), (axes.px(range.max), y + 9.0), grey, Align::Centre, Valign::Top);
    if target.is_finite() {
        c.line((axes.px(target), y - 12.0), (axes.px(target), y + 12.0), 3.0, INK);
    }
    for (v, colour, dy) in [(before, BEFORE, -3.0), (after, AFTER, 3.0)] {
        if v.is_finite() {
            c.disc((axes.px(v), y + dy), 6.0, colour);
        }
    }
    let mut x = BAND_TO + 24.0;
    for (v, colour) in [(target, INK), (before, BEFORE), (after, AFTER)] {
        let shown = if v.is_finite() { ticks::human(v) } else { "undefined".into() };
        x = text::draw(c, &shown, (x, y), NORMAL.colour(colour), Align::Left, Valign::Middle).x1 + 14.0;
    }
}
