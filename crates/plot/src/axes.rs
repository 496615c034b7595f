//! A rectangle of the picture that shows a data window: the linear map from data to pixels (y
//! up), and the frame with ticks at nice numbers, their labels and the axis titles (which carry
//! the unit, "easting x (m)").

use crate::canvas::{Canvas, GREY, INK, LIGHT_GREY, Point, Rect};
use crate::text::{self, Align, SMALL, Valign};
use crate::ticks;

/// Pixels between x ticks and between y ticks, about.
const X_TICK_SPACING: f64 = 90.0;
const Y_TICK_SPACING: f64 = 40.0;
/// Length of a tick mark outside the frame, pixels.
const TICK: f64 = 5.0;

/// Room around a frame for its tick labels and titles, pixels: left, bottom.
pub const LEFT: f64 = 72.0;
pub const BOTTOM: f64 = 46.0;

/// A data window drawn in `frame`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Axes {
    pub frame: Rect,
    /// Data interval across (left to right).
    pub x: (f64, f64),
    /// Data interval up (bottom to top).
    pub y: (f64, f64),
}

impl Axes {
    /// The window `x` × `y` in `frame`; an empty interval is widened by 0.5 on each side.
    pub fn new(frame: Rect, x: (f64, f64), y: (f64, f64)) -> Axes {
        Axes { frame, x: widen(x), y: widen(y) }
    }

    /// Pixel column of data `x`.
    pub fn px(&self, x: f64) -> f64 {
        self.frame.x0 + (x - self.x.0) / (self.x.1 - self.x.0) * self.frame.width()
    }

    /// Pixel row of data `y`.
    pub fn py(&self, y: f64) -> f64 {
        self.frame.y1 - (y - self.y.0) / (self.y.1 - self.y.0) * self.frame.height()
    }

    pub fn map(&self, (x, y): (f64, f64)) -> Point {
        (self.px(x), self.py(y))
    }

    /// Data units per pixel across.
    pub fn x_per_pixel(&self) -> f64 {
        (self.x.1 - self.x.0) / self.frame.width()
    }

    pub fn x_ticks(&self) -> Vec<f64> {
        ticks::ticks(self.x.0, self.x.1, (self.frame.width() / X_TICK_SPACING).round().max(2.0) as usize)
    }

    pub fn y_ticks(&self) -> Vec<f64> {
        ticks::ticks(self.y.0, self.y.1, (self.frame.height() / Y_TICK_SPACING).round().max(2.0) as usize)
    }

    /// Light grid lines at the y ticks (draw before the data).
    pub fn draw_y_grid(&self, canvas: &mut Canvas) {
        for t in self.y_ticks() {
            let y = self.py(t);
            canvas.line((self.frame.x0, y), (self.frame.x1, y), 1.0, LIGHT_GREY);
        }
    }

    /// The frame, ticks, tick labels and titles (draw after the data).
    pub fn draw(&self, canvas: &mut Canvas, x_title: &str, y_title: &str) {
        canvas.stroke_rect(self.frame, 1.0, GREY);
        let bottom = self.draw_x_ticks(canvas);
        text::draw(
            canvas,
            x_title,
            ((self.frame.x0 + self.frame.x1) / 2.0, bottom + 3.0),
            text::NORMAL,
            Align::Centre,
            Valign::Top,
        );
        let left = self.draw_y_ticks(canvas);
        let centre = (left - 4.0, (self.frame.y0 + self.frame.y1) / 2.0);
        text::draw_rotated(canvas, y_title, centre, text::NORMAL, (Align::Centre, Valign::Bottom), -90.0);
    }

    /// Ticks and labels below the frame; returns the lowest pixel row used.
    fn draw_x_ticks(&self, canvas: &mut Canvas) -> f64 {
        let ticks = self.x_ticks();
        let step = step_of(&ticks);
        let mut bottom = self.frame.y1 + TICK;
        for t in ticks {
            let x = self.px(t);
            canvas.line((x, self.frame.y1), (x, self.frame.y1 + TICK), 1.0, INK);
            let label = ticks::format(t, step);
            bottom = bottom.max(
                text::draw(
                    canvas,
                    &label,
                    (x, self.frame.y1 + TICK + 2.0),
                    SMALL,
                    Align::Centre,
                    Valign::Top,
                )
                .y1,
            );
        }
        bottom
    }

    /// Ticks and labels left of the frame; returns the leftmost pixel column used.
    fn draw_y_ticks(&self, canvas: &mut Canvas) -> f64 {
        let ticks = self.y_ticks();
        let step = step_of(&ticks);
        let mut left = self.frame.x0 - TICK;
        for t in ticks {
            let y = self.py(t);
            canvas.line((self.frame.x0 - TICK, y), (self.frame.x0, y), 1.0, INK);
            let label = ticks::format(t, step);
            left = left.min(
                text::draw(
                    canvas,
                    &label,
                    (self.frame.x0 - TICK - 3.0, y),
                    SMALL,
                    Align::Right,
                    Valign::Middle,
                )
                .x0,
            );
        }
        left
    }
}

/// The spacing of evenly spaced ticks (1 for fewer than two).
fn step_of(ticks: &[f64]) -> f64 {
    if ticks.len() >= 2 { ticks[1] - ticks[0] } else { ticks.first().map_or(1.0, |t| t.abs().max(1.0)) }
}

fn widen((lo, hi): (f64, f64)) -> (f64, f64) {
    if hi > lo { (lo, hi) } else { (lo - 0.5, lo + 0.5) }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::canvas::WHITE;

    #[test]
    fn maps_data_onto_the_frame_with_y_up() {
        let a = Axes::new(Rect::at(100.0, 50.0, 200.0, 100.0), (0.0, 10.0), (-1.0, 1.0));
        assert_eq!(a.map((0.0, -1.0)), (100.0, 150.0));
        assert_eq!(a.map((10.0, 1.0)), (300.0, 50.0));
        assert_eq!(a.x_per_pixel(), 0.05);
        let flat = Axes::new(a.frame, (3.0, 3.0), (0.0, 1.0));
        assert_eq!(flat.px(3.0), 200.0);
    }

    #[test]
    fn ticks_and_titles_are_drawn_outside_the_frame() {
        let mut c = Canvas::new(400, 300, WHITE);
        let a = Axes::new(Rect::at(LEFT, 20.0, 300.0, 200.0), (0.0, 500.0), (100.0, 300.0));
        a.draw(&mut c, "easting x (m)", "elevation z (m)");
        let inked = |r: Rect| {
            (r.y0 as i64..r.y1 as i64).any(|y| (r.x0 as i64..r.x1 as i64).any(|x| c.get(x, y) != Some(WHITE)))
        };
        assert!(inked(Rect::at(LEFT, 221.0, 300.0, BOTTOM)), "x labels");
        assert!(inked(Rect::at(0.0, 20.0, LEFT - 1.0, 200.0)), "y labels");
        assert!(!inked(Rect::at(LEFT + 2.0, 22.0, 296.0, 196.0)), "inside stays clear");
        assert_eq!(a.x_ticks(), vec![0.0, 200.0, 400.0]);
    }
}
