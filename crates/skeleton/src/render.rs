//! `karst-skeleton render`: a PNG with the network seen from above (x right, y up) and from the
//! south (x right, z up), conduits coloured by type, key points marked and named, and a legend.
//! Both views share one metric scale so that lengths compare.

use glam::DVec3;
use karst_raster::{BLACK, Canvas, Rgb, Scale, WHITE};

use crate::{ConduitType, Skeleton};

/// Width of the picture, pixels.
const WIDTH: u32 = 1000;
/// Margin around and between the views, pixels.
const MARGIN: f64 = 30.0;

/// Colour of a conduit type.
pub fn colour(kind: ConduitType) -> Rgb {
    match kind {
        ConduitType::Epikarst => [120, 180, 60],
        ConduitType::Tube => [200, 60, 160],
        ConduitType::Canyon => [230, 130, 30],
        ConduitType::Keyhole => [200, 180, 0],
        ConduitType::Passage => [150, 90, 50],
        ConduitType::Bed => [30, 90, 220],
        ConduitType::Chamber => [220, 30, 30],
    }
}

/// Draws `skeleton` (titled `title`).
pub fn render(skeleton: &Skeleton, title: &str) -> Canvas {
    let points: Vec<DVec3> = skeleton.nodes.iter().map(|n| DVec3::from_array(n.position)).collect();
    let (lo, hi) =
        points.iter().fold((DVec3::splat(f64::INFINITY), DVec3::splat(f64::NEG_INFINITY)), |(lo, hi), p| {
            (lo.min(*p), hi.max(*p))
        });
    let (lo, hi) = if points.is_empty() { (DVec3::ZERO, DVec3::ONE) } else { (lo, hi) };
    let span = (hi - lo).max(DVec3::splat(1.0));
    let metres_to_px = (f64::from(WIDTH) - 2.0 * MARGIN) / span.x.max(span.y);
    let top_h = span.y * metres_to_px;
    let side_h = span.z * metres_to_px;
    let height = (top_h + side_h + 4.0 * MARGIN + 40.0).ceil() as u32;
    let mut canvas = Canvas::new(WIDTH, height, WHITE);
    canvas.text((MARGIN as i64, 8), title, 2, BLACK);
    let x = Scale { from: (lo.x, lo.x + span.x), to: (MARGIN, MARGIN + span.x * metres_to_px) };
    let top = 2.0 * MARGIN;
    let y = Scale { from: (lo.y, lo.y + span.y), to: (top + top_h, top) };
    let side = top + top_h + MARGIN;
    let z = Scale { from: (lo.z, lo.z + span.z), to: (side + side_h, side) };
    canvas.text((MARGIN as i64, (top - 12.0) as i64), "top view", 1, BLACK);
    canvas.text((MARGIN as i64, (side - 12.0) as i64), "side view (from the south)", 1, BLACK);
    let views: [&dyn Fn(DVec3) -> (f64, f64); 2] =
        [&|p: DVec3| (x.map(p.x), y.map(p.y)), &|p: DVec3| (x.map(p.x), z.map(p.z))];
    for view in views {
        for conduit in &skeleton.conduits {
            for (w, kind) in conduit.nodes.windows(2).zip(&conduit.types) {
                let [a, b] = [w[0], w[1]].map(|i| view(points[i as usize]));
                canvas.line(a, b, 2.0, colour(*kind));
            }
        }
        for (node, p) in skeleton.nodes.iter().zip(&points) {
            if let Some(name) = &node.keypoint {
                let (px, py) = view(*p);
                canvas.disc((px, py), 4.0, BLACK);
                canvas.text((px as i64 + 6, py as i64 - 4), name, 1, BLACK);
            }
        }
    }
    legend(&mut canvas, skeleton, height);
    canvas
}

/// One swatch per type present, along the bottom edge.
fn legend(canvas: &mut Canvas, skeleton: &Skeleton, height: u32) {
    let mut at = MARGIN;
    let row = f64::from(height) - 20.0;
    for kind in ConduitType::ALL {
        if skeleton.length_of_type(kind) > 0.0 {
            canvas.rect((at, row), (at + 14.0, row + 8.0), colour(kind));
            let width = canvas.text((at as i64 + 18, row as i64), kind.name(), 1, BLACK);
            at += 18.0 + width as f64 + 14.0;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::{Conduit, Node, Zone};

    #[test]
    fn conduits_are_drawn_in_their_type_colour() {
        let node = |p: [f64; 3], k: Option<&str>| Node {
            position: p,
            sample: 0,
            keypoint: k.map(String::from),
            zone: Zone::Vadose,
        };
        let skeleton = Skeleton {
            nodes: vec![
                node([0.0, 0.0, 0.0], Some("a")),
                node([100.0, 0.0, 0.0], None),
                node([100.0, 100.0, 50.0], Some("b")),
            ],
            conduits: vec![Conduit {
                nodes: vec![0, 1, 2],
                radius: vec![1.0; 3],
                types: vec![ConduitType::Bed, ConduitType::Canyon],
                phase: 0,
                keypoints: vec!["a".into(), "b".into()],
            }],
            routes: vec![],
        };
        let canvas = render(&skeleton, "t");
        let count = |c: Rgb| {
            (0..canvas.height as i64)
                .flat_map(|y| (0..canvas.width as i64).map(move |x| (x, y)))
                .filter(|&(x, y)| canvas.get(x, y) == Some(c))
                .count()
        };
        assert!(count(colour(ConduitType::Bed)) > 500);
        assert!(count(colour(ConduitType::Canyon)) > 500);
        assert_eq!(count(colour(ConduitType::Tube)), 0);
    }
}
