//! `karst-streams render`: the map view of the surface network over the terrain (hill-shaded
//! grey, darker lower), each segment coloured by its water type (the hydro render's colours),
//! free falls thick, pools and lakes filled, spring mouths as black dots, with a legend. All
//! drawing is in this module, so that it can move to a shared plotting crate as one piece.

use glam::DVec2;

use karst_geology::Scene;
use karst_hydro::render::colour;
use karst_hydro::water::WaterType;
use karst_raster::{BLACK, Canvas, Rgb, Scale, WHITE};

use crate::artifact::{Motion, Outline, Streams};

const MAP: u32 = 800;
const MARGIN: f64 = 16.0;
const LEGEND: u32 = 130;

/// The map of `streams` over the terrain of `scene`.
pub fn map(scene: &Scene, streams: &Streams) -> Canvas {
    let d = &scene.domain;
    let span = (d.max[0] - d.min[0]).max(d.max[1] - d.min[1]).max(1e-9);
    let size = MAP as f64 - 2.0 * MARGIN;
    let sx = Scale { from: (d.min[0], d.min[0] + span), to: (MARGIN, MARGIN + size) };
    let sy = Scale { from: (d.min[1], d.min[1] + span), to: (MARGIN + size, MARGIN) };
    let mut canvas = Canvas::new(MAP + LEGEND, MAP, WHITE);
    shade(&mut canvas, scene, span / size, (sx, sy));
    let at = |p: [f64; 3]| (sx.map(p[0]), sy.map(p[1]));
    let px = size / span;
    let pool_colour = colour(WaterType::Pool);
    for pool in &streams.pools {
        match &pool.outline {
            Outline::Disc { centre, radius } => {
                canvas.disc(at([centre[0], centre[1], 0.0]), (radius * px).max(2.0), pool_colour)
            }
            Outline::Cells { rectangles } => {
                for r in rectangles {
                    canvas.rect(at([r[0], r[3], 0.0]), at([r[2], r[1], 0.0]), pool_colour);
                }
            }
            Outline::Polygon { points } => {
                for k in 0..points.len() {
                    let (a, b) = (points[k], points[(k + 1) % points.len()]);
                    canvas.line(at([a[0], a[1], 0.0]), at([b[0], b[1], 0.0]), 2.0, pool_colour);
                }
            }
        }
    }
    for s in &streams.segments {
        let (a, b) = (streams.nodes[s.from as usize].position, streams.nodes[s.to as usize].position);
        let thickness = if s.motion == Motion::FreeFall { 5.0 } else { 1.5 + 0.4 * s.flow_units.max(1.0) };
        canvas.line(at(a), at(b), thickness.max(s.width * px), colour(s.water));
    }
    for mouth in streams.springs.iter().filter_map(|s| s.mouth) {
        canvas.disc(at(mouth), 3.5, BLACK);
    }
    legend(&mut canvas, streams);
    canvas
}

/// Grey hill shading of the terrain, lighter higher, lit from the north-west.
fn shade(canvas: &mut Canvas, scene: &Scene, metres_per_pixel: f64, (sx, sy): (Scale, Scale)) {
    let d = &scene.domain;
    let height = |p: DVec2| scene.terrain.height(p.x, p.y);
    let (lo, hi) = (d.min[2], d.max[2]);
    let light = glam::DVec3::new(-1.0, 1.0, 1.5).normalize();
    let (x0, x1) = (sx.map(d.min[0]).floor() as i64, sx.map(d.max[0]).ceil() as i64);
    let (y0, y1) = (sy.map(d.max[1]).floor() as i64, sy.map(d.min[1]).ceil() as i64);
    for y in y0..y1 {
        for x in x0..x1 {
            let p = DVec2::new(
                d.min[0] + (x as f64 + 0.5 - MARGIN) * metres_per_pixel,
                d.min[1] + (MAP as f64 - MARGIN - y as f64 - 0.5) * metres_per_pixel,
            );
            let e = metres_per_pixel;
            let g = DVec2::new(
                height(p + DVec2::X * e) - height(p - DVec2::X * e),
                height(p + DVec2::Y * e) - height(p - DVec2::Y * e),
            ) / (2.0 * e);
            let normal = glam::DVec3::new(-g.x, -g.y, 1.0).normalize();
            let lit = normal.dot(light).clamp(0.0, 1.0);
            let t = ((height(p) - lo) / (hi - lo).max(1e-9)).clamp(0.0, 1.0);
            let v = (90.0 + 100.0 * t + 60.0 * lit).min(250.0) as u8;
            canvas.set(x, y, [v, v, v]);
        }
    }
}

fn legend(canvas: &mut Canvas, streams: &Streams) {
    let left = MAP as f64 + 6.0;
    canvas.text((left as i64, 6), "water type", 1, BLACK);
    let present: Vec<(WaterType, f64)> = streams.lengths();
    let mut row = 0;
    for w in WaterType::ALL {
        if w == WaterType::Sump {
            continue;
        }
        let top = 24.0 + 18.0 * row as f64;
        let c: Rgb = colour(w);
        canvas.rect((left, top), (left + 12.0, top + 10.0), c);
        let metres = present.iter().find(|(t, _)| *t == w).map_or(0.0, |(_, l)| *l);
        let label = if metres > 0.0 { format!("{} {metres:.0}m", w.name()) } else { w.name().to_string() };
        canvas.text((left as i64 + 16, top as i64 + 1), &label, 1, BLACK);
        row += 1;
    }
}
