//! `karst-hydro render`: the network seen from above (x, y) and from the south (x, z), each
//! segment coloured by its water type, dry conduits in light grey, with a legend.

use karst_raster::{BLACK, Canvas, Rgb, Scale, WHITE};
use karst_skeleton::Skeleton;

use crate::payload::Hydro;
use crate::water::WaterType;

/// Colour of a water type: blues for contact water, warm colours for free falls.
pub fn colour(water: WaterType) -> Rgb {
    match water {
        WaterType::Stream => [120, 190, 240],
        WaterType::River => [30, 110, 220],
        WaterType::Rapid => [0, 170, 170],
        WaterType::Cascade => [0, 140, 90],
        WaterType::Horsetail => [150, 200, 60],
        WaterType::Block => [90, 90, 20],
        WaterType::Ribbon => [250, 200, 40],
        WaterType::Plunge => [250, 140, 0],
        WaterType::Ledge => [220, 60, 30],
        WaterType::Cataract => [170, 0, 60],
        WaterType::Sump => [20, 20, 120],
        WaterType::Pool => [160, 80, 200],
        WaterType::Dry => [205, 205, 205],
    }
}

const VIEW: u32 = 600;
const MARGIN: f64 = 20.0;
const LEGEND: u32 = 130;

/// The picture of `hydro` on `skeleton`.
pub fn picture(skeleton: &Skeleton, hydro: &Hydro) -> Canvas {
    let mut canvas = Canvas::new(2 * VIEW + LEGEND, VIEW, WHITE);
    let axis = |i: usize| {
        let values = skeleton.nodes.iter().map(|n| n.position[i]);
        values.fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), v| (lo.min(v), hi.max(v)))
    };
    let (x, y, z) = (axis(0), axis(1), axis(2));
    let span = (x.1 - x.0).max(y.1 - y.0).max(z.1 - z.0).max(1.0);
    let px = |lo: f64, left: f64| Scale {
        from: (lo, lo + span),
        to: (left + MARGIN, left + VIEW as f64 - MARGIN),
    };
    let py = |lo: f64| Scale { from: (lo, lo + span), to: (VIEW as f64 - MARGIN, MARGIN) };
    let views = [(px(x.0, 0.0), py(y.0), 1usize), (px(x.0, VIEW as f64), py(z.0), 2usize)];
    // Dry first, so that water is drawn over it.
    for dry_pass in [true, false] {
        for (conduit, water) in skeleton.conduits.iter().zip(&hydro.conduits) {
            for (w, s) in conduit.nodes.windows(2).zip(&water.segments) {
                if (s.water == WaterType::Dry) != dry_pass {
                    continue;
                }
                let [a, b] = [w[0], w[1]].map(|n| skeleton.nodes[n as usize].position);
                let thickness = if dry_pass { 1.0 } else { 1.5 + s.flow_units.max(1.0) * 0.5 };
                for (sx, sy, v) in &views {
                    canvas.line(
                        (sx.map(a[0]), sy.map(a[*v])),
                        (sx.map(b[0]), sy.map(b[*v])),
                        thickness,
                        colour(s.water),
                    );
                }
            }
        }
    }
    canvas.text((MARGIN as i64, 4), "top (x, y)", 1, BLACK);
    canvas.text((VIEW as i64 + MARGIN as i64, 4), "side (x, z)", 1, BLACK);
    for (i, w) in WaterType::ALL.iter().enumerate() {
        let top = 30.0 + 18.0 * i as f64;
        let left = 2.0 * VIEW as f64 + 8.0;
        canvas.rect((left, top), (left + 12.0, top + 10.0), colour(*w));
        canvas.text((left as i64 + 18, top as i64 + 1), w.name(), 1, BLACK);
    }
    canvas
}
