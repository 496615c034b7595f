//! Point labels that do not collide. Each label is tried at candidate places around its point,
//! nearest first (right, upper right, lower right, left, upper left, lower left, above, below,
//! then rings further out in 16 directions, joined to the point by a leader line); it takes the
//! first candidate inside the bounds that overlaps no label already placed and no obstacle (the
//! markers). The most crowded points choose first, so that isolated ones, which have room
//! anywhere, do not take the few places a crowded one has. A label that finds no place is left
//! out, and the caller says so. Deterministic: ties keep the input order.

use crate::canvas::{Point, Rect};

/// Gap between a point and its label on the first ring, pixels.
pub const GAP: f64 = 5.0;
/// Distance between rings, pixels.
const STEP: f64 = 7.0;
/// Rings tried, the first included.
const RINGS: usize = 24;

/// A label to place: the point it names and the size of its text box.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Request {
    pub anchor: Point,
    pub size: (f64, f64),
}

/// Boxes for `requests` (same order), `None` where no free place was found.
pub fn place(requests: &[Request], obstacles: &[Rect], bounds: Rect) -> Vec<Option<Rect>> {
    let mut placed: Vec<Option<Rect>> = vec![None; requests.len()];
    let mut taken: Vec<Rect> = Vec::with_capacity(requests.len());
    for i in crowded_first(requests) {
        let free = |r: &Rect| {
            bounds.contains(r)
                && !taken.iter().any(|t| t.overlaps(r))
                && !obstacles.iter().any(|o| o.overlaps(r))
        };
        if let Some(r) = candidates(&requests[i]).find(free) {
            taken.push(r);
            placed[i] = Some(r);
        }
    }
    placed
}

/// Whether a placed box sits away from its point, so that a leader line should join them.
pub fn needs_leader(anchor: Point, rect: &Rect) -> bool {
    let (x, y) = rect.nearest(anchor);
    (x - anchor.0).hypot(y - anchor.1) > GAP * 1.5 + 1.0
}

/// Indices ordered by the number of other points within reach of a label, most first.
fn crowded_first(requests: &[Request]) -> Vec<usize> {
    let neighbours = |r: &Request| {
        let reach = r.size.0 + r.size.1;
        requests
            .iter()
            .filter(|o| (o.anchor.0 - r.anchor.0).abs() < reach && (o.anchor.1 - r.anchor.1).abs() < reach)
            .count()
    };
    let counts: Vec<usize> = requests.iter().map(neighbours).collect();
    let mut order: Vec<usize> = (0..requests.len()).collect();
    order.sort_by_key(|&i| std::cmp::Reverse(counts[i]));
    order
}

/// Candidate boxes around the point, nearest first.
fn candidates(r: &Request) -> impl Iterator<Item = Rect> + '_ {
    // The first ring in cartographers' order of preference, then 16 directions.
    const FIRST: [(f64, f64); 8] = [
        (1.0, 0.0),
        (1.0, -1.0),
        (1.0, 1.0),
        (-1.0, 0.0),
        (-1.0, -1.0),
        (-1.0, 1.0),
        (0.0, -1.0),
        (0.0, 1.0),
    ];
    let first = FIRST.iter().map(move |&d| around(r, d, GAP));
    let outer = (1..RINGS).flat_map(move |k| {
        (0..16).map(move |j| {
            let a = std::f64::consts::TAU * f64::from(j) / 16.0;
            around(r, (a.cos(), -a.sin()), GAP + STEP * k as f64)
        })
    });
    first.chain(outer)
}

/// The box on side `(dx, dy)` of the anchor (each component −1..1), `gap` away from it.
fn around(r: &Request, (dx, dy): (f64, f64), gap: f64) -> Rect {
    let (w, h) = r.size;
    let cx = r.anchor.0 + dx * (gap + w / 2.0);
    let cy = r.anchor.1 + dy * (gap + h / 2.0);
    Rect::at(cx - w / 2.0, cy - h / 2.0, w, h)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn an_isolated_label_goes_right_of_its_point() {
        let req = [Request { anchor: (50.0, 50.0), size: (30.0, 10.0) }];
        let placed = place(&req, &[], Rect::at(0.0, 0.0, 200.0, 200.0));
        assert_eq!(placed[0], Some(Rect::at(50.0 + GAP, 45.0, 30.0, 10.0)));
        assert!(!needs_leader((50.0, 50.0), &placed[0].unwrap()));
    }

    #[test]
    fn a_label_at_the_right_edge_goes_left() {
        let req = [Request { anchor: (190.0, 50.0), size: (30.0, 10.0) }];
        let placed = place(&req, &[], Rect::at(0.0, 0.0, 200.0, 200.0))[0].unwrap();
        assert!(placed.x1 <= 190.0 - GAP + 1e-9, "{placed:?}");
    }

    #[test]
    fn crowded_labels_never_overlap_each_other_or_the_markers() {
        // 47 points (as many as the looping preset's key points) packed in a 300 × 200 box,
        // several of them nearly on top of each other.
        let anchors: Vec<Point> = (0..47)
            .map(|i| {
                let t = f64::from(i);
                (150.0 + 120.0 * (t * 2.4).cos() * (t / 47.0), 100.0 + 80.0 * (t * 2.4).sin() * (t / 47.0))
            })
            .collect();
        let requests: Vec<Request> =
            anchors.iter().map(|&a| Request { anchor: a, size: (62.0, 14.0) }).collect();
        let markers: Vec<Rect> = anchors.iter().map(|a| Rect::at(a.0 - 3.0, a.1 - 3.0, 6.0, 6.0)).collect();
        let bounds = Rect::at(0.0, 0.0, 420.0, 320.0);
        let placed = place(&requests, &markers, bounds);
        let boxes: Vec<Rect> = placed.iter().flatten().copied().collect();
        assert!(boxes.len() >= 40, "only {} of 47 placed", boxes.len());
        for (i, a) in boxes.iter().enumerate() {
            assert!(bounds.contains(a));
            assert!(boxes[i + 1..].iter().all(|b| !a.overlaps(b)), "{a:?} overlaps another label");
            assert!(markers.iter().all(|m| !a.overlaps(m)), "{a:?} covers a marker");
        }
    }

    #[test]
    fn placement_is_deterministic() {
        let requests: Vec<Request> = (0..30)
            .map(|i| Request { anchor: (f64::from(i % 5) * 9.0, f64::from(i / 5) * 7.0), size: (40.0, 12.0) })
            .collect();
        let bounds = Rect::at(-100.0, -100.0, 300.0, 300.0);
        assert_eq!(place(&requests, &[], bounds), place(&requests, &[], bounds));
    }
}
