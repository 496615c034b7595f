//! Map furniture for views from above: a scale bar of a round length and a north arrow (north is
//! +y in every karstgen scene, so up on the picture). Each is drawn on a white box at a given
//! place; [`corner`] finds the place in a corner of a frame, and [`emptiest_corner`] the corner
//! that hides the fewest features.

use crate::axes::Axes;
use crate::canvas::{BLACK, Canvas, INK, Point, Rect, WHITE};
use crate::text::{self, Align, SMALL, Valign};
use crate::ticks;

/// Target length of the scale bar, pixels (it is at most this long).
const SCALE_BAR: f64 = 140.0;
const BAR_HEIGHT: f64 = 6.0;
/// Inset of the furniture from the frame, pixels.
const INSET: f64 = 8.0;
/// Size of the north arrow's box, pixels.
pub const NORTH_ARROW: (f64, f64) = (22.0, 44.0);

/// A corner of a frame.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Corner {
    BottomLeft,
    BottomRight,
    TopLeft,
    TopRight,
}

impl Corner {
    pub const ALL: [Corner; 4] = [Corner::BottomLeft, Corner::BottomRight, Corner::TopLeft, Corner::TopRight];
}

/// The box of `size` in `corner` of `frame`, inset a little.
pub fn corner(frame: Rect, corner: Corner, (w, h): (f64, f64)) -> Rect {
    let x = match corner {
        Corner::BottomLeft | Corner::TopLeft => frame.x0 + INSET,
        Corner::BottomRight | Corner::TopRight => frame.x1 - INSET - w,
    };
    let y = match corner {
        Corner::TopLeft | Corner::TopRight => frame.y0 + INSET,
        Corner::BottomLeft | Corner::BottomRight => frame.y1 - INSET - h,
    };
    Rect::at(x, y, w, h)
}

/// Of `corners` (in order of preference), the one whose box of `size` holds the fewest of
/// `features` (pixel positions).
pub fn emptiest_corner(frame: Rect, size: (f64, f64), corners: &[Corner], features: &[Point]) -> Corner {
    let hidden = |c: &Corner| {
        let r = corner(frame, *c, size).inflate(2.0);
        features.iter().filter(|p| p.0 >= r.x0 && p.0 <= r.x1 && p.1 >= r.y0 && p.1 <= r.y1).count()
    };
    *corners.iter().min_by_key(|c| hidden(c)).expect("at least one corner")
}

/// The largest 1, 2 or 5 × 10^k not above `raw` (`raw` > 0).
fn nice_below(raw: f64) -> f64 {
    let power = 10f64.powf(raw.log10().floor());
    let m = raw / power;
    [5.0, 2.0, 1.0].into_iter().find(|&n| n <= m + 1e-9).unwrap_or(1.0) * power
}

/// The bar's length in pixels and its label, for the scale of `axes` (metres across).
fn scale_bar_length(axes: &Axes) -> (f64, String) {
    let metres = nice_below(SCALE_BAR.min(axes.frame.width() / 3.0) * axes.x_per_pixel());
    (metres / axes.x_per_pixel(), format!("{} m", ticks::format(metres, metres)))
}

/// Size of the scale bar's box for `axes`.
pub fn scale_bar_size(axes: &Axes) -> (f64, f64) {
    let (length_px, label) = scale_bar_length(axes);
    let (w, h) = text::measure(&label, SMALL.size);
    (length_px.max(w) + 8.0, BAR_HEIGHT + h + 8.0)
}

/// Draws the scale bar (two halves, black and white, under its length) in its box at `at`.
pub fn draw_scale_bar(canvas: &mut Canvas, axes: &Axes, at: Point) {
    let (length_px, label) = scale_bar_length(axes);
    let (w, h) = scale_bar_size(axes);
    let area = Rect::at(at.0, at.1, w, h);
    canvas.fill_rect(area, WHITE);
    let (x0, y1) = (area.x0 + 4.0, area.y1 - 4.0);
    let bar = Rect::at(x0, y1 - BAR_HEIGHT, length_px, BAR_HEIGHT);
    canvas.fill_rect(Rect { x1: x0 + length_px / 2.0, ..bar }, BLACK);
    canvas.stroke_rect(bar, 1.0, BLACK);
    text::draw(canvas, &label, (x0, bar.y0 - 2.0), SMALL, Align::Left, Valign::Bottom);
}

/// Draws a north arrow (pointing up, "N" under it) in its box at `at`.
pub fn draw_north_arrow(canvas: &mut Canvas, at: Point) {
    let area = Rect::at(at.0, at.1, NORTH_ARROW.0, NORTH_ARROW.1);
    canvas.fill_rect(area, WHITE);
    let cx = (area.x0 + area.x1) / 2.0;
    let tip: Point = (cx, area.y0 + 3.0);
    let base = area.y0 + 24.0;
    canvas.fill_polygon(&[tip, (cx + 7.0, base), (cx, base - 6.0)], INK);
    canvas.fill_polygon(&[tip, (cx - 7.0, base), (cx, base - 6.0)], [170, 170, 170]);
    text::draw(canvas, "N", (cx, base + 1.0), SMALL, Align::Centre, Valign::Top);
}

/// Size of the north arrow over the scale bar, for a panel beside a map.
pub fn panel_size(axes: &Axes) -> (f64, f64) {
    let (w, h) = scale_bar_size(axes);
    (w.max(NORTH_ARROW.0), NORTH_ARROW.1 + 6.0 + h)
}

/// Draws the north arrow over the scale bar from `at` (top left), beside a map whose frame is
/// all data.
pub fn draw_panel(canvas: &mut Canvas, axes: &Axes, at: Point) {
    draw_north_arrow(canvas, at);
    draw_scale_bar(canvas, axes, (at.0, at.1 + NORTH_ARROW.1 + 6.0));
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_scale_bar_is_a_round_length_of_at_most_its_target() {
        assert_eq!(nice_below(140.0), 100.0);
        assert_eq!(nice_below(0.7), 0.5);
        assert_eq!(nice_below(3.0), 2.0);
        // 1 px = 2 m: 140 px would be 280 m, so 200 m = 100 px.
        let axes = Axes::new(Rect::at(0.0, 0.0, 600.0, 400.0), (0.0, 1200.0), (0.0, 800.0));
        assert_eq!(scale_bar_length(&axes), (100.0, "200 m".to_string()));
        let mut c = Canvas::new(600, 400, WHITE);
        let bar = corner(axes.frame, Corner::BottomLeft, scale_bar_size(&axes));
        let arrow = corner(axes.frame, Corner::TopRight, NORTH_ARROW);
        draw_scale_bar(&mut c, &axes, (bar.x0, bar.y0));
        draw_north_arrow(&mut c, (arrow.x0, arrow.y0));
        assert!(!bar.overlaps(&arrow) && axes.frame.contains(&bar) && axes.frame.contains(&arrow));
        assert_eq!(c.get(bar.x0 as i64 + 8, bar.y1 as i64 - 7), Some(BLACK));
    }

    #[test]
    fn furniture_goes_where_it_hides_least() {
        let frame = Rect::at(0.0, 0.0, 400.0, 300.0);
        let crowded_bottom_left: Vec<Point> = (0..20).map(|i| (20.0 + f64::from(i), 280.0)).collect();
        let c = emptiest_corner(frame, (60.0, 30.0), &Corner::ALL, &crowded_bottom_left);
        assert_eq!(c, Corner::BottomRight);
        assert_eq!(emptiest_corner(frame, (60.0, 30.0), &Corner::ALL, &[]), Corner::BottomLeft);
    }
}
