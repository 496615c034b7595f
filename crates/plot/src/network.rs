//! The picture of a conduit network, shared by `karst-skeleton render` (conduits by type) and
//! `karst-hydro render` (segments by water type): the view from above (easting right, northing
//! up, with a scale bar and a north arrow) over the view from the south (easting right,
//! elevation up), both at one metric scale and aligned on x so that a feature sits at the same
//! column in both; key points marked and named without overlaps (leader lines where a name
//! had to move away); a legend and notes below. The side view is stretched vertically only when
//! it would otherwise be flatter than [`MIN_SIDE`] pixels, and then says by how much.

use crate::axes::{self, Axes};
use crate::canvas::{BLACK, Canvas, GREY, Point, Rect, Rgb, WHITE};
use crate::labels::{self, Request};
use crate::legend::{self, Entry};
use crate::map::{self, Corner};
use crate::text::{self, Align, NORMAL, SMALL, Style, TITLE, Valign};

/// Widest picture, pixels (narrower when the network is tall: the views keep their shape).
pub const WIDTH: u32 = 1000;
/// Narrowest picture, pixels, so that the legend has room.
const MIN_WIDTH: f64 = 640.0;
/// Right margin, pixels.
const RIGHT: f64 = 24.0;
/// Tallest top view, pixels.
const MAX_TOP: f64 = 1000.0;
/// Flattest side view before it is exaggerated, pixels.
pub const MIN_SIDE: f64 = 120.0;
/// Top of the first frame: room for the title and the caption.
const FIRST_FRAME: f64 = 70.0;
/// Room for a view's caption above its frame.
const CAPTION: f64 = 26.0;
const LABEL: Style = Style::new(11.5).halo();
const MARKER: f64 = 3.2;

/// One straight piece of conduit, drawn `width` pixels wide.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Segment {
    pub a: [f64; 3],
    pub b: [f64; 3],
    pub colour: Rgb,
    pub width: f64,
}

/// A named point (sink, spring, waypoint).
#[derive(Debug, Clone, PartialEq)]
pub struct KeyPoint {
    pub position: [f64; 3],
    pub name: String,
}

/// What to draw.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct NetworkPicture {
    pub title: String,
    /// Drawn in order, later ones on top.
    pub segments: Vec<Segment>,
    pub key_points: Vec<KeyPoint>,
    pub legend: Vec<Entry>,
    /// Sentences printed under the legend.
    pub notes: Vec<String>,
}

/// The two views and how much the side view is stretched.
struct Layout {
    top: Axes,
    side: Axes,
    exaggeration: f64,
}

impl NetworkPicture {
    /// Draws the picture, at most [`WIDTH`] pixels wide.
    pub fn render(&self) -> Canvas {
        let layout = self.layout();
        let top_view = |p: [f64; 3]| layout.top.map((p[0], p[1]));
        let top_boxes = self.furniture(&layout.top, &top_view);
        let side_view = |p: [f64; 3]| layout.side.map((p[0], p[2]));
        let top_labels = self.place_labels(&top_view, layout.top.frame, &top_boxes);
        let side_labels = self.place_labels(&side_view, layout.side.frame, &[]);
        let mut notes = self.notes.clone();
        notes.extend(unplaced_note("top", &self.key_points, &top_labels));
        notes.extend(unplaced_note("side", &self.key_points, &side_labels));
        let width = (layout.top.frame.x1 + RIGHT).round().clamp(MIN_WIDTH, f64::from(WIDTH));
        let text_width = width - axes::LEFT - RIGHT;
        let legend_top = layout.side.frame.y1 + axes::BOTTOM + 12.0;
        let notes_top = legend_top + legend::flowed_height(&self.legend, text_width) + 6.0;
        let lines: Vec<String> = notes.iter().flat_map(|n| text::wrap(n, SMALL.size, text_width)).collect();
        let line_height = text::measure("M", SMALL.size).1 + 2.0;
        let height = notes_top + line_height * lines.len() as f64 + 12.0;

        let mut canvas = Canvas::new(width.ceil() as u32, height.ceil() as u32, WHITE);
        text::draw(&mut canvas, &self.title, (axes::LEFT, 12.0), TITLE, Align::Left, Valign::Top);
        let side_caption = match layout.exaggeration {
            e if e > 1.0 => format!("Side view from the south (vertical exaggeration ×{e})"),
            _ => "Side view from the south".to_string(),
        };
        for (axes, caption) in [(&layout.top, "Top view"), (&layout.side, side_caption.as_str())] {
            text::draw(
                &mut canvas,
                caption,
                (axes.frame.x0, axes.frame.y0 - 6.0),
                NORMAL,
                Align::Left,
                Valign::Bottom,
            );
        }
        self.draw_view(&mut canvas, &top_view, &top_labels);
        map::draw_scale_bar(&mut canvas, &layout.top, (top_boxes[0].x0, top_boxes[0].y0));
        map::draw_north_arrow(&mut canvas, (top_boxes[1].x0, top_boxes[1].y0));
        layout.top.draw(&mut canvas, "easting x (m)", "northing y (m)");
        self.draw_view(&mut canvas, &side_view, &side_labels);
        layout.side.draw(&mut canvas, "easting x (m)", "elevation z (m)");
        legend::draw_flowed(&mut canvas, &self.legend, (axes::LEFT, legend_top), text_width);
        for (i, line) in lines.iter().enumerate() {
            let y = notes_top + line_height * i as f64;
            text::draw(&mut canvas, line, (axes::LEFT, y), SMALL, Align::Left, Valign::Top);
        }
        canvas
    }

    /// The frames: one scale for both views, fitted to the width (and to [`MAX_TOP`]).
    fn layout(&self) -> Layout {
        let points =
            self.segments.iter().flat_map(|s| [s.a, s.b]).chain(self.key_points.iter().map(|k| k.position));
        let (mut lo, mut hi) = ([f64::INFINITY; 3], [f64::NEG_INFINITY; 3]);
        for p in points.filter(|p| p.iter().all(|v| v.is_finite())) {
            for k in 0..3 {
                lo[k] = lo[k].min(p[k]);
                hi[k] = hi[k].max(p[k]);
            }
        }
        if lo[0] > hi[0] {
            (lo, hi) = ([0.0; 3], [1.0; 3]);
        }
        let pad = 0.03 * (hi[0] - lo[0]).max(hi[1] - lo[1]).max(10.0);
        let range = |k: usize| (lo[k] - pad, hi[k] + pad);
        let span = |k: usize| hi[k] - lo[k] + 2.0 * pad;
        let scale = ((f64::from(WIDTH) - axes::LEFT - RIGHT) / span(0)).min(MAX_TOP / span(1));
        let top = Rect::at(axes::LEFT, FIRST_FRAME, span(0) * scale, span(1) * scale);
        let flat = span(2) * scale;
        let exaggeration = if flat < MIN_SIDE { (MIN_SIDE / flat).ceil() } else { 1.0 };
        let side = Rect::at(axes::LEFT, top.y1 + axes::BOTTOM + CAPTION, top.width(), flat * exaggeration);
        Layout {
            top: Axes::new(top, range(0), range(1)),
            side: Axes::new(side, range(0), range(2)),
            exaggeration,
        }
    }

    /// Boxes of the scale bar and the north arrow in the top view: the corners that hide the
    /// fewest conduit ends and key points (the scale bar preferably at the bottom).
    fn furniture(&self, top: &Axes, view: &dyn Fn([f64; 3]) -> Point) -> [Rect; 2] {
        let features: Vec<Point> = self
            .segments
            .iter()
            .flat_map(|s| [s.a, s.b])
            .chain(self.key_points.iter().map(|k| k.position))
            .map(view)
            .collect();
        let bar_size = map::scale_bar_size(top);
        let bar = map::emptiest_corner(top.frame, bar_size, &Corner::ALL, &features);
        let others: Vec<Corner> =
            [Corner::TopRight, Corner::TopLeft, Corner::BottomRight, Corner::BottomLeft]
                .into_iter()
                .filter(|c| *c != bar)
                .collect();
        let arrow = map::emptiest_corner(top.frame, map::NORTH_ARROW, &others, &features);
        [map::corner(top.frame, bar, bar_size), map::corner(top.frame, arrow, map::NORTH_ARROW)]
    }

    /// Label boxes for the key points in one view.
    fn place_labels(
        &self,
        view: &dyn Fn([f64; 3]) -> Point,
        frame: Rect,
        furniture: &[Rect],
    ) -> Vec<Option<Rect>> {
        let anchors: Vec<Point> = self.key_points.iter().map(|k| view(k.position)).collect();
        let requests: Vec<Request> = self
            .key_points
            .iter()
            .zip(&anchors)
            .map(|(k, &anchor)| Request { anchor, size: text::measure(&k.name, LABEL.size) })
            .collect();
        let mut obstacles: Vec<Rect> = anchors.iter().map(|a| marker_box(*a)).collect();
        obstacles.extend_from_slice(furniture);
        labels::place(&requests, &obstacles, frame.inflate(-2.0))
    }

    /// Segments, then markers, leader lines and names on top.
    fn draw_view(&self, canvas: &mut Canvas, view: &dyn Fn([f64; 3]) -> Point, names: &[Option<Rect>]) {
        for s in &self.segments {
            canvas.line(view(s.a), view(s.b), s.width, s.colour);
        }
        for (k, rect) in self.key_points.iter().zip(names) {
            let at = view(k.position);
            if let Some(r) = rect.filter(|r| labels::needs_leader(at, r)) {
                canvas.line(at, r.nearest(at), 1.0, GREY);
            }
        }
        for k in &self.key_points {
            let at = view(k.position);
            canvas.disc(at, MARKER + 1.5, WHITE);
            canvas.disc(at, MARKER, BLACK);
        }
        for (k, rect) in self.key_points.iter().zip(names) {
            if let Some(r) = rect {
                text::draw(canvas, &k.name, (r.x0, r.y0), LABEL, Align::Left, Valign::Top);
            }
        }
    }
}

fn marker_box((x, y): Point) -> Rect {
    let r = MARKER + 1.5;
    Rect::at(x - r, y - r, 2.0 * r, 2.0 * r)
}

/// "Not named in the side view (no room): a, b." when some labels found no place.
fn unplaced_note(view: &str, key_points: &[KeyPoint], placed: &[Option<Rect>]) -> Option<String> {
    let missing: Vec<&str> =
        key_points.iter().zip(placed).filter(|(_, p)| p.is_none()).map(|(k, _)| k.name.as_str()).collect();
    (!missing.is_empty()).then(|| format!("Not named in the {view} view (no room): {}.", missing.join(", ")))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::legend::Swatch;

    fn picture(n_points: usize) -> NetworkPicture {
        let segments = (0..40)
            .map(|i| {
                let t = f64::from(i);
                Segment {
                    a: [t * 10.0, t * 5.0, 100.0 - t / 2.0],
                    b: [t * 10.0 + 10.0, t * 5.0 + 5.0, 99.5 - t / 2.0],
                    colour: [200, 60, 160],
                    width: 2.0,
                }
            })
            .collect();
        let key_points = (0..n_points)
            .map(|i| KeyPoint {
                position: [f64::from(i as u32) * 8.0, f64::from(i as u32) * 4.0, 90.0],
                name: format!("sink-{i:02}"),
            })
            .collect();
        NetworkPicture {
            title: "test".into(),
            segments,
            key_points,
            legend: vec![Entry::new(Swatch::Line([200, 60, 160], 3.0), "tube")],
            notes: vec!["a note".into()],
        }
    }

    #[test]
    fn both_views_share_the_x_scale_and_flat_side_views_are_stretched() {
        let layout = picture(3).layout();
        assert_eq!(layout.top.frame.x0, layout.side.frame.x0);
        assert_eq!(layout.top.frame.x1, layout.side.frame.x1);
        assert_eq!(layout.top.x, layout.side.x);
        // 400 m across, 20 m high: the side view would be ~94 px, so it is stretched.
        assert!(layout.exaggeration >= 2.0, "{}", layout.exaggeration);
        assert!(layout.side.frame.height() >= MIN_SIDE);
    }

    #[test]
    fn the_picture_draws_the_segments_in_their_colour() {
        let canvas = picture(5).render();
        assert!(canvas.width() <= WIDTH);
        let pink = (0..canvas.height() as i64)
            .flat_map(|y| (0..canvas.width() as i64).map(move |x| (x, y)))
            .filter(|&(x, y)| canvas.get(x, y) == Some([200, 60, 160]))
            .count();
        assert!(pink > 1000, "{pink}");
    }

    #[test]
    fn names_with_no_room_are_listed_in_a_note() {
        let missing =
            unplaced_note("side", &picture(2).key_points, &[Some(Rect::at(0.0, 0.0, 1.0, 1.0)), None]);
        assert_eq!(missing.as_deref(), Some("Not named in the side view (no room): sink-01."));
    }
}
