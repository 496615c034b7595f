//! A preview picture of one surface or several: orthographic view from above one corner,
//! software z-buffer shared by the surfaces, flat Lambert shading; the first surface tinted by
//! elevation (deep passages dark blue, shallow ones sand), any other in one colour (the water
//! over the carved terrain), with a caption and the elevation tint's colour bar (karst-plot).

use glam::DVec3;
use karst_plot::colour_bar::{BAR_WIDTH, ColourBar, ColourMap};
use karst_plot::text::{self, Align, TITLE, Valign};
use karst_plot::{Canvas, Rect, Rgb};

use crate::payload::TriMesh;

/// Where the viewer stands: azimuth and elevation of the view direction, degrees.
const AZIMUTH: f64 = -60.0;
const ELEVATION: f64 = 35.0;
const BACKGROUND: Rgb = [245, 245, 240];
const DEEP: DVec3 = DVec3::new(40.0, 70.0, 140.0);
const SHALLOW: DVec3 = DVec3::new(225.0, 190.0, 130.0);

/// Width kept on the right for the colour bar, pixels.
const KEY: f64 = 110.0;

/// The elevation tint over `zlo..zhi`, unshaded.
fn tint(zlo: f64, zhi: f64) -> ColourBar {
    let [deep, shallow] = [DEEP, SHALLOW].map(|c| [c.x as u8, c.y as u8, c.z as u8]);
    ColourBar {
        map: ColourMap::new(&[(0.0, deep), (1.0, shallow)]),
        range: (zlo, zhi),
        title: "elevation (m)".into(),
    }
}

/// The colour of the water drawn over another surface, before shading.
pub const WATER: DVec3 = DVec3::new(60.0, 140.0, 230.0);

/// Renders `first` tinted by elevation and each of `others` in its colour, hiding one another,
/// on a `width` × `height` canvas with a caption.
pub fn render(
    first: &TriMesh,
    others: &[(&TriMesh, DVec3)],
    width: u32,
    height: u32,
    caption: &str,
) -> Canvas {
    let surface = first;
    let mut canvas = Canvas::new(width, height, BACKGROUND);
    let (az, el) = (AZIMUTH.to_radians(), ELEVATION.to_radians());
    let toward_viewer = DVec3::new(el.cos() * az.cos(), el.cos() * az.sin(), el.sin());
    let right = DVec3::new(-az.sin(), az.cos(), 0.0);
    let up = toward_viewer.cross(right);
    let light = (toward_viewer + up * 0.6 - right * 0.4).normalize();
    let project = |p: DVec3| DVec3::new(p.dot(right), -p.dot(up), p.dot(toward_viewer));
    let screens: Vec<Vec<DVec3>> = std::iter::once(surface)
        .chain(others.iter().map(|(s, _)| *s))
        .map(|s| (0..s.vertices.len() as u32).map(|v| project(s.position(v))).collect())
        .collect();
    let (lo, hi) = screens
        .iter()
        .flatten()
        .fold((DVec3::INFINITY, DVec3::NEG_INFINITY), |(lo, hi), &p| (lo.min(p), hi.max(p)));
    let (zlo, zhi) = (0..surface.vertices.len() as u32)
        .map(|v| surface.position(v).z)
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), z| (a.min(z), b.max(z)));
    let margin = 24.0;
    let top = 40.0;
    let key = if width as f64 > 3.0 * KEY { KEY } else { 0.0 };
    let scale = ((width as f64 - 2.0 * margin - key) / (hi.x - lo.x))
        .min((height as f64 - top - margin) / (hi.y - lo.y));
    let to_pixel = |p: DVec3| DVec3::new(margin + (p.x - lo.x) * scale, top + (p.y - lo.y) * scale, p.z);
    let mut depth = vec![f64::NEG_INFINITY; width as usize * height as usize];
    let layers = std::iter::once((surface, None)).chain(others.iter().map(|(s, c)| (*s, Some(*c))));
    for ((surface, flat), screen) in layers.zip(&screens) {
        for t in &surface.triangles {
            let n = surface.normal(t).normalize_or_zero();
            if n.dot(toward_viewer) <= 0.0 {
                continue;
            }
            let base = flat.unwrap_or_else(|| {
                let z = t.iter().map(|&v| surface.position(v).z).sum::<f64>() / 3.0;
                DEEP.lerp(SHALLOW, if zhi > zlo { (z - zlo) / (zhi - zlo) } else { 0.5 })
            });
            let shade = 0.3 + 0.7 * n.dot(light).max(0.0);
            let colour = (base * shade).min(DVec3::splat(255.0));
            let colour = [colour.x as u8, colour.y as u8, colour.z as u8];
            let corners = t.map(|v| to_pixel(screen[v as usize]));
            fill(&mut canvas, &mut depth, corners, colour);
        }
    }
    text::draw(&mut canvas, caption, (margin, 12.0), TITLE, Align::Left, Valign::Top);
    if key > 0.0 && zhi > zlo {
        let bar_h = (height as f64 * 0.4).min(240.0);
        let bar =
            Rect::at(width as f64 - key + 10.0, top + ColourBar::title_height() + 4.0, BAR_WIDTH, bar_h);
        tint(zlo, zhi).draw(&mut canvas, bar);
    }
    canvas
}

/// Fills a triangle whose pixels are nearer than what is drawn (larger z is nearer).
fn fill(canvas: &mut Canvas, depth: &mut [f64], [a, b, c]: [DVec3; 3], colour: Rgb) {
    let area = edge(a, b, c);
    if area.abs() < 1e-12 {
        return;
    }
    let x0 = a.x.min(b.x).min(c.x).floor().max(0.0) as i64;
    let x1 = a.x.max(b.x).max(c.x).ceil().min(canvas.width() as f64 - 1.0) as i64;
    let y0 = a.y.min(b.y).min(c.y).floor().max(0.0) as i64;
    let y1 = a.y.max(b.y).max(c.y).ceil().min(canvas.height() as f64 - 1.0) as i64;
    for y in y0..=y1 {
        for x in x0..=x1 {
            let p = DVec3::new(x as f64 + 0.5, y as f64 + 0.5, 0.0);
            let (wa, wb, wc) = (edge(b, c, p) / area, edge(c, a, p) / area, edge(a, b, p) / area);
            if wa < 0.0 || wb < 0.0 || wc < 0.0 {
                continue;
            }
            let z = wa * a.z + wb * b.z + wc * c.z;
            let i = y as usize * canvas.width() as usize + x as usize;
            if z > depth[i] {
                depth[i] = z;
                canvas.set(x, y, colour);
            }
        }
    }
}

/// Twice the signed area of (a, b, p) in the screen plane.
fn edge(a: DVec3, b: DVec3, p: DVec3) -> f64 {
    (b.x - a.x) * (p.y - a.y) - (b.y - a.y) * (p.x - a.x)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A closed tetrahedron, counter-clockwise seen from outside.
    fn tetrahedron() -> TriMesh {
        TriMesh {
            vertices: vec![[0.0, 0.0, 0.0], [10.0, 0.0, 0.0], [0.0, 10.0, 0.0], [0.0, 0.0, 10.0]],
            triangles: vec![[0, 2, 1], [0, 1, 3], [0, 3, 2], [1, 2, 3]],
            ..TriMesh::default()
        }
    }

    #[test]
    fn the_render_decodes_at_its_size_with_the_surface_and_its_key() {
        let canvas = render(&tetrahedron(), &[], 480, 320, "cave 4 triangles at 1 m");
        let mut bytes = Vec::new();
        canvas.encode_png(&mut bytes).unwrap();
        let (w, h, colours) = karst_plot::testing::png_summary(&bytes);
        assert_eq!((w, h), (480, 320));
        assert!(colours > 20, "{colours} colours");
        // The colour bar runs from the lowest tint at its bottom to the highest at its top.
        let bar = tint(0.0, 10.0);
        let x = (480.0 - KEY + 10.0 + BAR_WIDTH / 2.0) as i64;
        let (y0, y1) =
            (40.0 + ColourBar::title_height() + 4.0, 40.0 + ColourBar::title_height() + 4.0 + 128.0);
        let near = |y: f64, v: f64| {
            let (got, want) = (canvas.get(x, y as i64).unwrap(), bar.colour(v));
            (0..3).all(|k| got[k].abs_diff(want[k]) <= 6)
        };
        assert!(near(y0 + 2.0, 10.0) && near(y1 - 2.0, 0.0));
    }

    #[test]
    fn a_second_surface_in_front_hides_the_first_in_its_colour() {
        // A small tetrahedron of water in front of (towards the viewer from) a large one.
        let rock = tetrahedron();
        let mut water = tetrahedron();
        for v in &mut water.vertices {
            *v = [v[0] * 0.3 + 8.0, v[1] * 0.3 - 6.0, v[2] * 0.3 + 4.0];
        }
        let alone = render(&rock, &[], 480, 320, "rock");
        let both = render(&rock, &[(&water, WATER)], 480, 320, "rock and water");
        let blue = |c: Rgb| c[2] > c[0] + 60 && c[2] > c[1] + 20;
        let count = |c: &Canvas| {
            (0..320)
                .flat_map(|y| (0..480).map(move |x| (x, y)))
                .filter(|&(x, y)| blue(c.get(x, y).unwrap()))
                .count()
        };
        assert!(count(&both) > count(&alone) + 50, "{} vs {}", count(&both), count(&alone));
    }
}
