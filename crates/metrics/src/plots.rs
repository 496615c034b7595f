//! Pictures of a network's statistics, drawn with karst-raster:
//!
//! - [`rose`]: the rose diagram of conduit azimuths, each 10° class a petal whose radius is
//!   proportional to the projected conduit length in the class (the histogram behind karstnet's
//!   orientation entropy; axial, so every petal is drawn on both sides of the centre);
//! - [`branch_length_histogram`]: the number of branches per length class, 20 classes from 0 to
//!   the longest branch;
//! - [`range_chart`]: each `characterize_graph()` metric on the real-cave range (grey band),
//!   green when inside, red when outside (or undefined).

use std::path::Path;

use karst_raster::{BLACK, Canvas, GREY, Rgb, Scale, WHITE};

use crate::ranges::Compared;

const GREEN: Rgb = [30, 150, 60];
const RED: Rgb = [210, 40, 40];
const PETAL: Rgb = [70, 110, 180];
const LIGHT: Rgb = [225, 225, 225];

/// Length-weighted rose diagram of 18 azimuth classes (N–S first, clockwise from north).
pub fn rose(azimuth_lengths: &[f64]) -> Canvas {
    let (size, radius) = (440u32, 180.0);
    let centre = (f64::from(size) / 2.0, f64::from(size) / 2.0 + 10.0);
    let mut c = Canvas::new(size, size, WHITE);
    let max = azimuth_lengths.iter().copied().fold(0.0, f64::max);
    let n = azimuth_lengths.len().max(1);
    for y in 0..size {
        for x in 0..size {
            let (east, north) = (f64::from(x) + 0.5 - centre.0, centre.1 - (f64::from(y) + 0.5));
            let r = east.hypot(north);
            let bearing = east.atan2(north).to_degrees().rem_euclid(180.0);
            let class = ((bearing / 180.0 * n as f64) as usize).min(n - 1);
            if max > 0.0 && r <= radius * azimuth_lengths[class] / max {
                c.set(i64::from(x), i64::from(y), PETAL);
            }
        }
    }
    for ring in [0.25, 0.5, 0.75, 1.0] {
        circle(&mut c, centre, radius * ring, GREY);
    }
    c.line((centre.0, centre.1 - radius), (centre.0, centre.1 + radius), 1.0, GREY);
    c.line((centre.0 - radius, centre.1), (centre.0 + radius, centre.1), 1.0, GREY);
    c.text((centre.0 as i64 - 4, (centre.1 - radius) as i64 - 12), "N", 1, BLACK);
    c.text(((centre.0 + radius) as i64 + 4, centre.1 as i64 - 4), "E", 1, BLACK);
    c.text((10, 8), "Conduit azimuths, weighted by projected length", 1, BLACK);
    c.text((10, size as i64 - 14), &format!("outer ring: {:.0} m per 10 deg", max), 1, BLACK);
    c
}

/// Number of branches per length class.
pub fn branch_length_histogram(lengths: &[f64]) -> Canvas {
    let (width, height) = (560u32, 360u32);
    let (left, right, top, bottom) = (60.0, 540.0, 30.0, 320.0);
    let mut c = Canvas::new(width, height, WHITE);
    let n_bins = 20;
    let max_length = lengths.iter().copied().fold(0.0, f64::max);
    let mut counts = vec![0usize; n_bins];
    for &l in lengths {
        let bin = if max_length > 0.0 { (l / max_length * n_bins as f64) as usize } else { 0 };
        counts[bin.min(n_bins - 1)] += 1;
    }
    let max_count = counts.iter().copied().max().unwrap_or(0).max(1);
    let xs = Scale { from: (0.0, n_bins as f64), to: (left, right) };
    let ys = Scale { from: (0.0, max_count as f64), to: (bottom, top) };
    for (i, &count) in counts.iter().enumerate() {
        c.rect((xs.map(i as f64) + 1.0, ys.map(count as f64)), (xs.map(i as f64 + 1.0) - 1.0, bottom), PETAL);
    }
    c.line((left, bottom), (right, bottom), 1.0, BLACK);
    c.line((left, bottom), (left, top), 1.0, BLACK);
    c.text((10, 8), &format!("Branch lengths ({} branches)", lengths.len()), 1, BLACK);
    c.text((4, top as i64), &max_count.to_string(), 1, BLACK);
    c.text((4, bottom as i64 - 8), "0", 1, BLACK);
    c.text((left as i64, bottom as i64 + 8), "0 m", 1, BLACK);
    let label = format!("{max_length:.1} m");
    c.text((right as i64 - 8 * label.len() as i64, bottom as i64 + 8), &label, 1, BLACK);
    c.text((left as i64 + 150, bottom as i64 + 24), "branch length (20 classes)", 1, BLACK);
    c
}

/// Each metric against its real-cave range: grey band = range, disc = value.
pub fn range_chart(compared: &[(&str, Compared)]) -> Canvas {
    let row = 36.0;
    let (left, right) = (230.0, 620.0);
    let height = (50.0 + row * compared.len() as f64) as u32;
    let mut c = Canvas::new(760, height, WHITE);
    c.text((10, 8), "Metrics against the real caves (Collon et al. 2017)", 1, BLACK);
    for (i, (key, m)) in compared.iter().enumerate() {
        let y = 40.0 + row * i as f64 + row / 2.0;
        let r = &m.real_caves;
        let lo = if m.value.is_finite() { r.min.min(m.value) } else { r.min };
        let hi = if m.value.is_finite() { r.max.max(m.value) } else { r.max };
        let pad = (hi - lo) * 0.08;
        let xs = Scale { from: (lo - pad, hi + pad), to: (left, right) };
        c.text((10, y as i64 - 4), key, 1, BLACK);
        c.rect((left, y - 1.0), (right, y + 1.0), LIGHT);
        c.rect((xs.map(r.min), y - 6.0), (xs.map(r.max), y + 6.0), GREY);
        let colour = if m.inside { GREEN } else { RED };
        if m.value.is_finite() {
            c.disc((xs.map(m.value), y), 6.0, colour);
        }
        let shown = if m.value.is_finite() { format!("{:.4}", m.value) } else { "undefined".into() };
        c.text((right as i64 + 14, y as i64 - 4), &shown, 1, colour);
        let bounds = format!("{:.3} .. {:.3}", r.min, r.max);
        c.text((xs.map(r.min) as i64, y as i64 + 9), &bounds, 1, GREY);
    }
    c
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

fn circle(c: &mut Canvas, centre: (f64, f64), r: f64, colour: Rgb) {
    let steps = (r * 8.0).max(16.0) as usize;
    for s in 0..steps {
        let a = std::f64::consts::TAU * s as f64 / steps as f64;
        c.set((centre.0 + r * a.cos()) as i64, (centre.1 + r * a.sin()) as i64, colour);
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::ranges::CaveRange;

    #[test]
    fn rose_petals_point_along_the_conduits() {
        // All length in the 0°–10° class: a petal just east of north and its opposite just west of
        // south; nothing to the east.
        let mut classes = vec![0.0; 18];
        classes[0] = 100.0;
        let c = rose(&classes);
        assert_eq!(c.get(223, 230 - 150), Some(PETAL));
        assert_eq!(c.get(217, 230 + 150), Some(PETAL));
        assert_eq!(c.get(223, 230 + 150), Some(WHITE));
        assert_eq!(c.get(220 + 150, 200), Some(WHITE));
    }

    #[test]
    fn range_chart_colours_inside_green_and_outside_red() {
        let range = CaveRange { min: 1.0, max: 2.0, min_network: "a".into(), max_network: "b".into(), n: 3 };
        let rows = [
            ("in", Compared { value: 1.5, real_caves: range.clone(), inside: true }),
            ("out", Compared { value: 5.0, real_caves: range, inside: false }),
        ];
        let c = range_chart(&rows);
        let count = |colour: Rgb| {
            (0..c.height as i64)
                .flat_map(|y| (0..c.width as i64).map(move |x| (x, y)))
                .filter(|&(x, y)| c.get(x, y) == Some(colour))
                .count()
        };
        assert!(count(GREEN) > 50 && count(RED) > 50);
    }

    #[test]
    fn histogram_puts_the_longest_branch_in_the_last_class() {
        let c = branch_length_histogram(&[1.0, 1.0, 10.0]);
        // Classes are 24 px wide from x = 60: the two 1 m branches fill class 2 to the top, the
        // 10 m branch class 19 to mid-height.
        assert_eq!(c.get(530, 300), Some(PETAL));
        assert_eq!(c.get(530, 100), Some(WHITE));
        assert_eq!(c.get(120, 100), Some(PETAL));
        assert_eq!(c.get(70, 100), Some(WHITE));
    }
}
