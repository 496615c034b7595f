//! Pictures of a network's statistics, drawn with karst-plot:
//!
//! - [`rose`]: the rose diagram of conduit azimuths, each 10° class a petal whose radius is
//!   proportional to the projected conduit length in the class (the histogram behind karstnet's
//!   orientation entropy; axial, so every petal is drawn on both sides of the centre), with
//!   rings at round lengths;
//! - [`branch_length_histogram`]: the number of branches per length class, the classes chosen
//!   for the data (Freedman–Diaconis, Sturges for fewer than 20 branches), each branch also
//!   marked under the bars;
//! - [`range_chart`]: each `characterize_graph()` metric on the real-cave range (grey band),
//!   green when inside, red when outside (or undefined).

use std::f64::consts::PI;
use std::path::Path;

use karst_plot::axes::{self, Axes};
use karst_plot::bins::Bins;
use karst_plot::legend::{self, Entry, Swatch};
use karst_plot::text::{self, Align, NORMAL, SMALL, TITLE, Valign};
use karst_plot::{Canvas, GREY, INK, LIGHT_GREY, Point, Rect, Rgb, WHITE, ticks};

use crate::ranges::Compared;

const GREEN: Rgb = [30, 150, 60];
const RED: Rgb = [210, 40, 40];
const PETAL: Rgb = [70, 110, 180];
const BAND: Rgb = [200, 200, 200];

/// The rose: picture size, centre and outer radius, pixels.
const ROSE_SIZE: (u32, u32) = (560, 600);
const ROSE_CENTRE: Point = (280.0, 300.0);
const ROSE_RADIUS: f64 = 200.0;

/// Length-weighted rose diagram of the azimuth classes (N–S first, clockwise from north).
pub fn rose(azimuth_lengths: &[f64]) -> Canvas {
    let mut c = Canvas::new(ROSE_SIZE.0, ROSE_SIZE.1, WHITE);
    let (centre, radius) = (ROSE_CENTRE, ROSE_RADIUS);
    let max = azimuth_lengths.iter().copied().fold(0.0, f64::max);
    let at = |bearing: f64, r: f64| (centre.0 + r * bearing.sin(), centre.1 - r * bearing.cos());
    for bearing in (0..12).map(|k| f64::from(k) * PI / 6.0) {
        c.line(centre, at(bearing, radius), 1.0, LIGHT_GREY);
    }
    let width = PI / azimuth_lengths.len().max(1) as f64;
    for (i, &length) in azimuth_lengths.iter().enumerate() {
        let r = if max > 0.0 { radius * length / max } else { 0.0 };
        for side in [0.0, PI] {
            let from = i as f64 * width + side;
            let mut petal = vec![centre];
            petal.extend((0..=16).map(|k| at(from + width * f64::from(k) / 16.0, r)));
            c.fill_polygon(&petal, PETAL);
        }
    }
    let rings = ticks::ticks(0.0, max, 4);
    let step = if rings.len() >= 2 { rings[1] - rings[0] } else { 1.0 };
    for &ring in rings.iter().filter(|&&v| v > 0.0) {
        let r = radius * ring / max;
        c.circle(centre, r, 1.0, GREY);
        let label = format!("{} m", ticks::format(ring, step));
        text::draw(&mut c, &label, at(PI * 0.42, r), SMALL.halo(), Align::Left, Valign::Bottom);
    }
    for (name, bearing) in [("N", 0.0), ("E", PI / 2.0), ("S", PI), ("W", 1.5 * PI)] {
        text::draw(&mut c, name, at(bearing, radius + 14.0), NORMAL, Align::Centre, Valign::Middle);
    }
    text::draw(
        &mut c,
        "Conduit azimuths, weighted by projected length",
        (16.0, 12.0),
        TITLE,
        Align::Left,
        Valign::Top,
    );
    let total: f64 = azimuth_lengths.iter().sum();
    let caption = format!(
        "Petal radius: horizontal length per {}° class (axial, drawn both ways); {} m in all.",
        ticks::human(180.0 / azimuth_lengths.len().max(1) as f64),
        ticks::human(total)
    );
    text::draw(&mut c, &caption, (16.0, f64::from(ROSE_SIZE.1) - 14.0), SMALL, Align::Left, Valign::Bottom);
    c
}

/// The histogram's picture size and frame, pixels.
const HISTOGRAM_SIZE: (u32, u32) = (640, 440);
const HISTOGRAM_FRAME: Rect = Rect { x0: axes::LEFT, y0: 64.0, x1: 616.0, y1: 440.0 - axes::BOTTOM - 8.0 };

/// The histogram's axes for `bins` and the largest class count.
fn histogram_axes(bins: &Bins, most: usize) -> Axes {
    let top = (most as f64 * 1.1).max(5.0);
    Axes::new(HISTOGRAM_FRAME, (bins.start, bins.edge(bins.count)), (0.0, top))
}

/// Number of branches per length class.
pub fn branch_length_histogram(lengths: &[f64]) -> Canvas {
    let mut c = Canvas::new(HISTOGRAM_SIZE.0, HISTOGRAM_SIZE.1, WHITE);
    let bins = Bins::choose(lengths);
    let counts = bins.counts(lengths);
    let axes = histogram_axes(&bins, counts.iter().copied().max().unwrap_or(0));
    axes.draw_y_grid(&mut c);
    for (k, &count) in counts.iter().enumerate().filter(|(_, n)| **n > 0) {
        let (x0, x1) = (axes.px(bins.edge(k)) + 1.0, axes.px(bins.edge(k + 1)) - 1.0);
        c.fill_rect(Rect { x0, y0: axes.py(count as f64), x1, y1: axes.frame.y1 }, PETAL);
    }
    for &l in lengths.iter().filter(|l| l.is_finite()) {
        let x = axes.px(l);
        c.line((x, axes.frame.y1 - 7.0), (x, axes.frame.y1 - 1.0), 1.0, INK);
    }
    axes.draw(&mut c, "branch length (m)", "branches");
    text::draw(
        &mut c,
        &format!("Branch lengths of {} branches", lengths.len()),
        (16.0, 12.0),
        TITLE,
        Align::Left,
        Valign::Top,
    );
    let subtitle = format!(
        "{} classes of {} m ({} rule); ticks under the bars mark each branch",
        bins.count,
        ticks::human(bins.width),
        bins.rule.name()
    );
    text::draw(&mut c, &subtitle, (16.0, 38.0), SMALL, Align::Left, Valign::Top);
    c
}

/// The range chart's layout, pixels: row height, metric names' column, band from..to.
const ROW: f64 = 40.0;
const BAND_FROM: f64 = 240.0;
const BAND_TO: f64 = 620.0;
const CHART_TOP: f64 = 80.0;

/// Each metric against its real-cave range: grey band = range, disc = value.
pub fn range_chart(compared: &[(&str, Compared)]) -> Canvas {
    let height = (CHART_TOP + ROW * compared.len() as f64 + 16.0) as u32;
    let mut c = Canvas::new(780, height, WHITE);
    text::draw(
        &mut c,
        "Metrics against the real caves (Collon et al. 2017)",
        (16.0, 12.0),
        TITLE,
        Align::Left,
        Valign::Top,
    );
    let key = [
        Entry::new(Swatch::Patch(BAND), "range of the real caves"),
        Entry::new(Swatch::Dot(GREEN), "inside"),
        Entry::new(Swatch::Dot(RED), "outside or undefined"),
    ];
    legend::draw_flowed(&mut c, &key, (16.0, 42.0), 740.0);
    for (i, (key, m)) in compared.iter().enumerate() {
        let y = CHART_TOP + ROW * i as f64 + ROW / 2.0 - 4.0;
        if i > 0 {
            c.line((16.0, y - ROW / 2.0), (764.0, y - ROW / 2.0), 1.0, LIGHT_GREY);
        }
        draw_range_row(&mut c, key, m, y);
    }
    c
}

/// One metric's row centred on pixel row `y`.
fn draw_range_row(c: &mut Canvas, key: &str, m: &Compared, y: f64) {
    let r = &m.real_caves;
    let (lo, hi) =
        if m.value.is_finite() { (r.min.min(m.value), r.max.max(m.value)) } else { (r.min, r.max) };
    let pad = (hi - lo) * 0.08;
    let axes = Axes::new(
        Rect { x0: BAND_FROM, y0: y - 6.0, x1: BAND_TO, y1: y + 6.0 },
        (lo - pad, hi + pad),
        (0.0, 1.0),
    );
    text::draw(c, key, (16.0, y), NORMAL, Align::Left, Valign::Middle);
    c.fill_rect(Rect { x0: axes.px(r.min), y0: y - 6.0, x1: axes.px(r.max), y1: y + 6.0 }, BAND);
    let colour = if m.inside { GREEN } else { RED };
    if m.value.is_finite() {
        c.disc((axes.px(m.value), y), 6.0, colour);
    }
    text::draw(
        c,
        &ticks::human(m.value),
        (BAND_TO + 16.0, y),
        NORMAL.colour(colour),
        Align::Left,
        Valign::Middle,
    );
    let bounds = SMALL.colour(GREY);
    text::draw(c, &ticks::human(r.min), (axes.px(r.min), y + 8.0), bounds, Align::Centre, Valign::Top);
    text::draw(c, &ticks::human(r.max), (axes.px(r.max), y + 8.0), bounds, Align::Centre, Valign::Top);
}

/// Writes the three pictures into `dir` as `metrics-rose.png`, `metrics-branch-lengths.png` and
/// `metrics-ranges.png`.
pub fn write_all(
    dir: &Path,
    azimuth_lengths: &[f64],
    branch_lengths: &[f64],
    compared: &[(&str, Compared)],
) -> std::io::Result<()> {
    std::fs::create_dir_all(dir)?;
    rose(azimuth_lengths).write_png(&dir.join("metrics-rose.png"))?;
    branch_length_histogram(branch_lengths).write_png(&dir.join("metrics-branch-lengths.png"))?;
    range_chart(compared).write_png(&dir.join("metrics-ranges.png"))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::ranges::CaveRange;

    fn count(c: &Canvas, colour: Rgb) -> usize {
        (0..c.height() as i64)
            .flat_map(|y| (0..c.width() as i64).map(move |x| (x, y)))
            .filter(|&(x, y)| c.get(x, y) == Some(colour))
            .count()
    }

    #[test]
    fn rose_petals_point_along_the_conduits() {
        // All length in the 0°–10° class: a petal just east of north and its opposite just west of
        // south; nothing to the east or just west of north.
        let mut classes = vec![0.0; 18];
        classes[0] = 100.0;
        let c = rose(&classes);
        let (cx, cy) = (ROSE_CENTRE.0 as i64, ROSE_CENTRE.1 as i64);
        assert_eq!(c.get(cx + 6, cy - 140), Some(PETAL));
        assert_eq!(c.get(cx - 6, cy + 140), Some(PETAL));
        assert_ne!(c.get(cx - 6, cy - 140), Some(PETAL));
        assert_ne!(c.get(cx + 150, cy - 20), Some(PETAL));
    }

    #[test]
    fn range_chart_colours_inside_green_and_outside_red() {
        let range = CaveRange { min: 1.0, max: 2.0, min_network: "a".into(), max_network: "b".into(), n: 3 };
        let rows = [
            ("in", Compared { value: 1.5, real_caves: range.clone(), inside: true }),
            ("out", Compared { value: 5.0, real_caves: range, inside: false }),
        ];
        let c = range_chart(&rows);
        assert!(count(&c, GREEN) > 100 && count(&c, RED) > 100);
        assert_eq!(c.height(), (CHART_TOP + 2.0 * ROW + 16.0) as u32);
    }

    #[test]
    fn histogram_classes_follow_the_data() {
        // Three branches: Sturges gives 3 classes over 9 m, 3 m rounded up to 5 m: [0, 5) holds
        // two branches, [5, 10) none, [10, 15) one.
        let lengths = [1.0, 1.0, 10.0];
        let bins = Bins::choose(&lengths);
        assert_eq!((bins.start, bins.width, bins.count), (0.0, 5.0, 3));
        let c = branch_length_histogram(&lengths);
        let axes = histogram_axes(&bins, 2);
        let probe = |x: f64, n: f64| c.get(axes.px(x) as i64, axes.py(n) as i64);
        assert_eq!(probe(2.5, 1.9), Some(PETAL));
        assert_ne!(probe(2.5, 2.2), Some(PETAL));
        assert_ne!(probe(7.5, 0.5), Some(PETAL));
        assert_eq!(probe(12.5, 0.9), Some(PETAL));
        assert_ne!(probe(12.5, 1.2), Some(PETAL));
    }

    #[test]
    fn nine_branches_get_few_classes() {
        let lengths = [12.0, 40.0, 95.0, 130.0, 180.0, 260.0, 300.0, 410.0, 1030.0];
        assert!(Bins::choose(&lengths).count <= 6);
        let mut bytes = Vec::new();
        branch_length_histogram(&lengths).encode_png(&mut bytes).unwrap();
        let (w, h, colours) = karst_plot::testing::png_summary(&bytes);
        assert_eq!((w, h), HISTOGRAM_SIZE);
        assert!(colours > 10);
    }

    #[test]
    fn pictures_decode_at_their_size_and_are_not_blank() {
        let dir = karst_testkit::scratch("metrics-plots");
        let range = CaveRange { min: 1.0, max: 2.0, min_network: "a".into(), max_network: "b".into(), n: 3 };
        let rows = [("x", Compared { value: f64::NAN, real_caves: range, inside: false })];
        write_all(&dir, &[1.0, 2.0, 3.0], &[5.0, 6.0], &rows).unwrap();
        for (file, size) in [
            ("metrics-rose.png", ROSE_SIZE),
            ("metrics-branch-lengths.png", HISTOGRAM_SIZE),
            ("metrics-ranges.png", (780, (CHART_TOP + ROW + 16.0) as u32)),
        ] {
            let (w, h, colours) = karst_plot::testing::png_summary(&std::fs::read(dir.join(file)).unwrap());
            assert_eq!((w, h), size, "{file}");
            assert!(colours > 10, "{file}: {colours} colours");
        }
    }
}
