//! The map of the surface network (`karstgen render streams`, `karst-streams render`): the
//! terrain hill-shaded in grey (lighter higher, lit from the north-west), each segment coloured
//! by its water type (the hydro render's colours) and widened with its flow, free falls thick,
//! pools and lakes filled, spring mouths as dots; axes in metres, a legend of the types present
//! with their lengths, a north arrow and a scale bar (karst-plot).

use glam::{DVec2, DVec3};

use karst_geology::{Domain, Terrain};
use karst_hydro::{WaterType, colour};
use karst_plot::axes::{self, Axes};
use karst_plot::legend::{self, Entry, Swatch};
use karst_plot::text::{self, Align, Valign};
use karst_plot::{BLACK, Canvas, Point, Rect, WHITE, ticks};

use crate::payload::{Motion, Outline, Streams};

/// The longer side of the map, pixels.
const MAP: f64 = 720.0;
/// Top of the map frame, under the title and caption, pixels.
const TOP: f64 = 64.0;

/// The map of `streams` over the terrain of the domain.
pub fn map(domain: &Domain, terrain: &Terrain, streams: &Streams) -> Canvas {
    let d = domain;
    let (w, h) = (d.max[0] - d.min[0], d.max[1] - d.min[1]);
    let zoom = MAP / w.max(h).max(1e-9);
    let frame = Rect::at(axes::LEFT, TOP, (w * zoom).max(1.0), (h * zoom).max(1.0));
    let map = Axes::new(frame, (d.min[0], d.max[0]), (d.min[1], d.max[1]));
    let entries = entries(streams);
    let side = (frame.x1 + 24.0, frame.y0);
    let (legend_w, legend_h) = legend::column_size(&entries);
    let (panel_w, panel_h) = karst_plot::map::panel_size(&map);
    let width = side.0 + legend_w.max(panel_w) + 16.0;
    let height = (frame.y1 + axes::BOTTOM + 8.0).max(side.1 + legend_h + 24.0 + panel_h + 8.0);
    let mut c = Canvas::new(width.ceil() as u32, height.ceil() as u32, WHITE);
    shade(&mut c, (domain, terrain), &map);
    draw_pools(&mut c, streams, &map);
    for s in &streams.segments {
        let [a, b] = [s.from, s.to].map(|n| at(&map, streams.nodes[n as usize].position));
        c.line(a, b, width_px(s.motion, s.flow_units).max(s.width * zoom), colour(s.water));
    }
    for mouth in streams.springs.iter().filter_map(|s| s.mouth) {
        c.disc(at(&map, mouth), 4.0, WHITE);
        c.disc(at(&map, mouth), 3.0, BLACK);
    }
    map.draw(&mut c, "easting x (m)", "northing y (m)");
    let bottom = legend::draw_column(&mut c, &entries, side);
    karst_plot::map::draw_panel(&mut c, &map, (side.0, bottom + 24.0));
    let title = "Surface water by type (Emilien et al. 2015, Table 1)";
    text::draw(&mut c, title, (axes::LEFT, 10.0), text::TITLE, Align::Left, Valign::Top);
    let caption = format!(
        "{} falls, {} pools; line width grows with the flow (1.5 px + 0.4 px per flow unit); terrain shaded",
        streams.falls(),
        streams.pools.len()
    );
    text::draw(&mut c, &caption, (axes::LEFT, 36.0), text::SMALL, Align::Left, Valign::Top);
    c
}

/// A node's position on the map.
fn at(map: &Axes, p: [f64; 3]) -> Point {
    map.map((p[0], p[1]))
}

/// Width of a segment, pixels: falls thick, running water 1.5 + 0.4 per flow unit.
fn width_px(motion: Motion, flow_units: f64) -> f64 {
    if motion == Motion::FreeFall { 5.0 } else { 1.5 + 0.4 * flow_units.max(1.0) }
}

/// The types present with their lengths, then pools and mouths.
fn entries(streams: &Streams) -> Vec<Entry> {
    let mut entries: Vec<Entry> = streams
        .lengths()
        .into_iter()
        .filter(|(w, _)| *w != WaterType::Pool)
        .map(|(w, metres)| {
            let motion = if w.is_free_fall() { Motion::FreeFall } else { Motion::Contact };
            Entry::new(
                Swatch::Line(colour(w), width_px(motion, 1.0)),
                format!("{} {} m", w.name(), ticks::human(metres)),
            )
        })
        .collect();
    if !streams.pools.is_empty() {
        entries.push(Entry::new(Swatch::Patch(colour(WaterType::Pool)), "pool / lake"));
    }
    entries.push(Entry::new(Swatch::Dot(BLACK), "spring mouth"));
    entries
}

/// The pools and lakes, filled.
fn draw_pools(c: &mut Canvas, streams: &Streams, map: &Axes) {
    let fill = colour(WaterType::Pool);
    for pool in &streams.pools {
        match &pool.outline {
            Outline::Disc { centre, radius } => {
                c.disc(map.map((centre[0], centre[1])), (radius / map.x_per_pixel()).max(2.0), fill)
            }
            Outline::Cells { rectangles } => {
                for r in rectangles {
                    let (a, b) = (map.map((r[0], r[3])), map.map((r[2], r[1])));
                    c.fill_rect(Rect { x0: a.0, y0: a.1, x1: b.0, y1: b.1 }, fill);
                }
            }
            Outline::Polygon { points } => {
                let points: Vec<Point> = points.iter().map(|p| map.map((p[0], p[1]))).collect();
                c.fill_polygon(&points, fill);
            }
        }
    }
}

/// Grey hill shading of the terrain inside the frame, lighter higher, lit from the north-west.
fn shade(c: &mut Canvas, (d, terrain): (&Domain, &Terrain), map: &Axes) {
    let height = |p: DVec2| terrain.height(p.x, p.y);
    let (lo, hi) = (d.min[2], d.max[2]);
    let light = DVec3::new(-1.0, 1.0, 1.5).normalize();
    let e = map.x_per_pixel();
    let f = map.frame;
    for y in f.y0.floor() as i64..f.y1.ceil() as i64 {
        for x in f.x0.floor() as i64..f.x1.ceil() as i64 {
            let p =
                DVec2::new(d.min[0] + (x as f64 + 0.5 - f.x0) * e, d.max[1] - (y as f64 + 0.5 - f.y0) * e);
            let g = DVec2::new(
                height(p + DVec2::X * e) - height(p - DVec2::X * e),
                height(p + DVec2::Y * e) - height(p - DVec2::Y * e),
            ) / (2.0 * e);
            let lit = DVec3::new(-g.x, -g.y, 1.0).normalize().dot(light).clamp(0.0, 1.0);
            let t = ((height(p) - lo) / (hi - lo).max(1e-9)).clamp(0.0, 1.0);
            let v = (90.0 + 100.0 * t + 60.0 * lit).min(250.0) as u8;
            c.set(x, y, [v, v, v]);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::payload::{Node, Role, Segment, SpringMouth};

    #[test]
    fn the_map_decodes_and_shows_the_stream_in_its_colour() {
        let text = karst_testkit::SceneText::new("m")
            .replace("[terrain]", "[terrain]\nkind = \"plane\"\nelevation = 45\ngradient = [-0.1, 0]")
            .text();
        let scene = karst_scene::Scene::parse(&text, std::path::Path::new("m.toml")).unwrap();
        let node = |x: f64, role| Node {
            position: [x, 25.0, 40.0 - 0.1 * x],
            role,
            source: 0.0,
            lateral: 0.0,
            inflow: 1.0,
        };
        let streams = Streams {
            flow_range: [0.005, 500.0],
            nodes: vec![node(10.0, Role::Source), node(90.0, Role::Well)],
            segments: vec![Segment {
                from: 0,
                to: 1,
                motion: Motion::Contact,
                curve: None,
                flow: 1.0,
                water: WaterType::River,
                slope: 0.1,
                flow_units: 4.0,
                look: None,
                speed: 1.0,
                width: 1.0,
                depth: 0.3,
                fall: None,
            }],
            pools: Vec::new(),
            springs: vec![SpringMouth {
                name: "s".into(),
                position: [10.0, 25.0, 30.0],
                mouth: Some([10.0, 25.0, 39.0]),
                node: Some(0),
                discharge: 1.0,
            }],
            reports: Vec::new(),
        };
        let canvas = map(scene.domain(), scene.terrain(), &streams);
        let mut bytes = Vec::new();
        canvas.encode_png(&mut bytes).unwrap();
        let (w, h, colours) = karst_plot::testing::png_summary(&bytes);
        assert!(w > MAP as u32 && h > MAP as u32 && colours > 20, "{w} × {h}, {colours} colours");
        let middle =
            Axes::new(Rect::at(axes::LEFT, TOP, MAP, MAP), (0.0, 100.0), (0.0, 100.0)).map((50.0, 25.0));
        assert_eq!(canvas.get(middle.0 as i64, middle.1 as i64), Some(colour(WaterType::River)));
    }
}
