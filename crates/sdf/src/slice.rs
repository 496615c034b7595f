//! Cross-section images of the model: a horizontal slice at height z, or a vertical one at
//! y or x = const (which cuts conduits across and shows their section shapes). The PNG shows rock
//! (grey, darker with depth into the rock, keyed by a colour bar), cave air (black), water
//! (blue) and air above the ground (white), with the karst outline (brown), on axes in metres;
//! water thinner than a pixel, which the pixel centres miss, is drawn light blue and noted under
//! the picture; horizontal slices have a north arrow and a scale bar beside them. The EXR stores the raw
//! fields (R: f, G: cave, B: water) for other tools.

use std::path::Path;

use glam::DVec3;
use karst_plot::axes::{self, Axes};
use karst_plot::colour_bar::{BAR_WIDTH, ColourBar, ColourMap};
use karst_plot::legend::{self, Entry, Swatch};
use karst_plot::text::{self, Align, SMALL, TITLE, Valign};
use karst_plot::{Canvas, Rect, Rgb, WHITE, map, ticks};

use crate::CarvedTerrain;

/// Which plane to cut.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Plane {
    /// Horizontal, at this height.
    Z(f64),
    /// Vertical, at this northing (x across the image).
    Y(f64),
    /// Vertical, at this easting (y across the image).
    X(f64),
}

/// A grid of points over the domain (or a window of it) in `plane`, `pixel` metres apart.
pub struct SliceGrid {
    pub width: usize,
    pub height: usize,
    /// In-plane ranges: (u0, v1) is the top-left corner.
    u0: f64,
    v1: f64,
    plane: Plane,
    pixel: f64,
}

impl SliceGrid {
    /// `window` = [u0, u1, v0, v1] in the plane's coordinates (x, y for z slices; x, z for y
    /// slices; y, z for x slices); the domain's extent when `None`.
    pub fn new(field: &CarvedTerrain, plane: Plane, pixel: f64, window: Option<[f64; 4]>) -> Self {
        let d = &field.model().domain;
        let [u0, u1, v0, v1] = window.unwrap_or(match plane {
            Plane::Z(_) => [d.min[0], d.max[0], d.min[1], d.max[1]],
            Plane::Y(_) => [d.min[0], d.max[0], d.min[2], d.max[2]],
            Plane::X(_) => [d.min[1], d.max[1], d.min[2], d.max[2]],
        });
        let size = |s: f64| ((s / pixel).ceil().max(1.0) as usize).min(8192);
        SliceGrid { width: size(u1 - u0), height: size(v1 - v0), u0, v1, plane, pixel }
    }

    /// The point of pixel (x, y), y down (north, or up, at the top).
    pub fn point(&self, x: usize, y: usize) -> DVec3 {
        self.point_at(x as f64 + 0.5, y as f64 + 0.5)
    }

    /// The point at fractional pixel position (x, y).
    fn point_at(&self, x: f64, y: f64) -> DVec3 {
        let u = self.u0 + x * self.pixel;
        let v = self.v1 - y * self.pixel;
        match self.plane {
            Plane::Z(z) => DVec3::new(u, v, z),
            Plane::Y(n) => DVec3::new(u, n, v),
            Plane::X(e) => DVec3::new(e, u, v),
        }
    }

    /// The in-plane window [u0, u1] × [v0, v1] the pixels cover.
    fn window(&self) -> ((f64, f64), (f64, f64)) {
        let (w, h) = (self.width as f64 * self.pixel, self.height as f64 * self.pixel);
        ((self.u0, self.u0 + w), (self.v1 - h, self.v1))
    }

    /// The plane's caption and the titles of its across and up axes.
    fn names(&self) -> (String, &'static str, &'static str) {
        match self.plane {
            Plane::Z(z) => (format!("z = {} m", ticks::plain(z)), "easting x (m)", "northing y (m)"),
            Plane::Y(n) => (format!("y = {} m", ticks::plain(n)), "easting x (m)", "elevation z (m)"),
            Plane::X(e) => (format!("x = {} m", ticks::plain(e)), "northing y (m)", "elevation z (m)"),
        }
    }
}

/// What a pixel shows.
#[derive(Debug, Clone, Copy, PartialEq)]
enum Cell {
    /// Rock this deep, metres.
    Rock(f64),
    Outline,
    Water,
    /// Water inside the pixel that its centre misses, with no water pixel beside it.
    ThinWater,
    CaveAir,
    Air,
}

const OUTLINE: Rgb = [150, 60, 20];
const WATER: Rgb = [40, 90, 220];
const THIN_WATER: Rgb = [120, 200, 255];
const CAVE_AIR: Rgb = [10, 10, 10];
const AIR: Rgb = [250, 250, 250];
/// Depth into the rock at which the grey stops darkening, metres.
const DEEP_ROCK: f64 = 40.0;
/// Sub-samples per pixel side when looking for water the centre misses.
const SUBSAMPLES: usize = 3;
/// Slices narrower than this many pixels are enlarged by whole pixels.
const MIN_PICTURE: f64 = 480.0;

fn rock_bar() -> ColourBar {
    ColourBar {
        map: ColourMap::new(&[(0.0, [170, 170, 160]), (1.0, [90, 90, 80])]),
        range: (0.0, DEEP_ROCK),
        title: "depth into rock (m)".into(),
    }
}

/// The three fields a slice shows: the model, or an analytic stand-in in the tests.
trait Fields {
    /// The carved terrain: negative in the rock.
    fn rock(&self, p: DVec3) -> f64;
    /// The karst volume: negative in the conduits.
    fn cave(&self, p: DVec3) -> f64;
    /// The water: negative in it.
    fn water(&self, p: DVec3) -> f64;
}

impl Fields for CarvedTerrain {
    fn rock(&self, p: DVec3) -> f64 {
        self.eval(p)
    }

    fn cave(&self, p: DVec3) -> f64 {
        CarvedTerrain::cave(self, p)
    }

    fn water(&self, p: DVec3) -> f64 {
        CarvedTerrain::water(self, p)
    }
}

/// The class of the pixel centre `p`.
fn centre_cell(field: &impl Fields, p: DVec3, pixel: f64) -> Cell {
    let f = field.rock(p);
    if f < 0.0 {
        return if field.cave(p).abs() < pixel * 0.7 { Cell::Outline } else { Cell::Rock(-f) };
    }
    if field.water(p) < 0.0 {
        Cell::Water
    } else if field.cave(p) < 0.0 {
        Cell::CaveAir
    } else {
        Cell::Air
    }
}

/// Whether water lies inside pixel (x, y) although its centre is dry: the nearest water is
/// within the pixel's half diagonal and one of its sub-samples is wet.
fn water_inside(field: &impl Fields, grid: &SliceGrid, x: usize, y: usize) -> bool {
    let (p, reach) = (grid.point(x, y), grid.pixel * std::f64::consts::FRAC_1_SQRT_2);
    if field.rock(p) < -reach || field.water(p) >= reach {
        return false;
    }
    let step = 1.0 / SUBSAMPLES as f64;
    (0..SUBSAMPLES * SUBSAMPLES).any(|k| {
        let (i, j) = ((k % SUBSAMPLES) as f64, (k / SUBSAMPLES) as f64);
        field.water(grid.point_at(x as f64 + (i + 0.5) * step, y as f64 + (j + 0.5) * step)) < 0.0
    })
}

/// Every pixel's class, thin water found.
fn cells(field: &impl Fields, grid: &SliceGrid) -> Vec<Cell> {
    let (w, h) = (grid.width, grid.height);
    let mut cells: Vec<Cell> =
        (0..w * h).map(|i| centre_cell(field, grid.point(i % w, i / w), grid.pixel)).collect();
    let wet_beside = |cells: &[Cell], x: usize, y: usize| {
        (y.saturating_sub(1)..(y + 2).min(h))
            .any(|j| (x.saturating_sub(1)..(x + 2).min(w)).any(|i| cells[j * w + i] == Cell::Water))
    };
    let thin: Vec<usize> = (0..w * h)
        .filter(|&i| {
            cells[i] != Cell::Water && matches!(cells[i], Cell::CaveAir | Cell::Outline | Cell::Rock(_))
        })
        .filter(|&i| !wet_beside(&cells, i % w, i / w) && water_inside(field, grid, i % w, i / w))
        .collect();
    for i in thin {
        cells[i] = Cell::ThinWater;
    }
    cells
}

fn colour(cell: Cell, rock: &ColourBar) -> Rgb {
    match cell {
        Cell::Rock(depth) => rock.colour(depth),
        Cell::Outline => OUTLINE,
        Cell::Water => WATER,
        Cell::ThinWater => THIN_WATER,
        Cell::CaveAir => CAVE_AIR,
        Cell::Air => AIR,
    }
}

/// The slice as a picture: the cells on axes in metres, a legend and the rock's colour bar on
/// the right, notes below.
pub fn picture(field: &CarvedTerrain, grid: &SliceGrid) -> Canvas {
    let cells = cells(field, grid);
    let rock = rock_bar();
    let thin = cells.iter().filter(|c| **c == Cell::ThinWater).count();
    let shown = |class: Cell| cells.contains(&class);
    let key: Vec<Entry> = [
        (Cell::CaveAir, "cave air"),
        (Cell::Water, "water"),
        (Cell::ThinWater, "water thinner than a pixel"),
        (Cell::Outline, "karst outline"),
        (Cell::Air, "air above ground"),
    ]
    .into_iter()
    .filter(|(class, _)| shown(*class))
    .map(|(class, name)| Entry::new(Swatch::Patch(colour(class, &rock)), name))
    .collect();
    let zoom = (MIN_PICTURE / grid.width.max(grid.height) as f64).floor().clamp(1.0, 8.0);
    let frame = Rect::at(axes::LEFT, 44.0, grid.width as f64 * zoom, grid.height as f64 * zoom);
    let (u, v) = grid.window();
    let axes = Axes::new(frame, u, v);
    let map_view = matches!(grid.plane, Plane::Z(_));
    let (key_w, key_h) = legend::column_size(&key);
    let panel_x = frame.x1 + 24.0;
    let bar = Rect::at(panel_x, frame.y0 + key_h + 16.0 + ColourBar::title_height(), BAR_WIDTH, 160.0);
    let furniture_at = (panel_x, bar.y1 + 20.0);
    let (furniture_w, furniture_h) = if map_view { map::panel_size(&axes) } else { (0.0, -20.0) };
    let width = panel_x + key_w.max(rock.width(bar.height())).max(furniture_w) + 16.0;
    let notes = thin_water_note(thin, grid.pixel);
    let lines: Vec<String> =
        notes.iter().flat_map(|n| text::wrap(n, SMALL.size, width - axes::LEFT - 16.0)).collect();
    let line_height = text::measure("M", SMALL.size).1 + 2.0;
    let notes_top = (frame.y1 + axes::BOTTOM + 8.0).max(furniture_at.1 + furniture_h + 12.0);
    let height = notes_top + line_height * lines.len() as f64 + 8.0;

    let mut canvas = Canvas::new(width.ceil() as u32, height.ceil() as u32, WHITE);
    for (i, cell) in cells.iter().enumerate() {
        let (x, y) = ((i % grid.width) as f64 * zoom, (i / grid.width) as f64 * zoom);
        canvas.fill_rect(Rect::at(frame.x0 + x, frame.y0 + y, zoom, zoom), colour(*cell, &rock));
    }
    let (caption, across, up) = grid.names();
    if map_view {
        map::draw_panel(&mut canvas, &axes, furniture_at);
    }
    axes.draw(&mut canvas, across, up);
    let title = format!("Slice at {caption}, {} m pixels", ticks::plain(grid.pixel));
    text::draw(&mut canvas, &title, (axes::LEFT, 10.0), TITLE, Align::Left, Valign::Top);
    legend::draw_column(&mut canvas, &key, (panel_x, frame.y0));
    rock.draw(&mut canvas, bar);
    for (i, line) in lines.iter().enumerate() {
        text::draw(
            &mut canvas,
            line,
            (axes::LEFT, notes_top + line_height * i as f64),
            SMALL,
            Align::Left,
            Valign::Top,
        );
    }
    canvas
}

/// The note under a slice whose pixels hide thin water.
fn thin_water_note(pixels: usize, pixel: f64) -> Option<String> {
    (pixels > 0).then(|| {
        format!(
            "Water thinner than the {} m pixel: {pixels} pixel(s) hold water their centre misses (light blue); \
             a smaller --pixel shows its shape.",
            ticks::plain(pixel)
        )
    })
}

/// Writes the PNG slice.
pub fn write_png(field: &CarvedTerrain, grid: &SliceGrid, path: &Path) -> std::io::Result<()> {
    picture(field, grid).write_png(path)
}

/// Writes the EXR slice: R = f, G = cave, B = water.
pub fn write_exr(field: &CarvedTerrain, grid: &SliceGrid, path: &Path) -> Result<(), exr::error::Error> {
    exr::prelude::write_rgb_file(path, grid.width, grid.height, |x, y| {
        let p = grid.point(x, y);
        (field.eval(p) as f32, field.cave(p) as f32, field.water(p) as f32)
    })
}

/// The cross-section library: one filled section per conduit type (radius 1, `ratio`,
/// `asymmetry`), side by side and named, `scale` pixels per metre, with a 1 m scale bar.
pub fn write_sections_png(ratio: f64, asymmetry: f64, scale: f64, path: &Path) -> std::io::Result<()> {
    sections_picture(ratio, asymmetry, scale).write_png(path)
}

/// The picture [`write_sections_png`] writes.
fn sections_picture(ratio: f64, asymmetry: f64, scale: f64) -> Canvas {
    use crate::tree::section::{Section, Shape};
    use karst_skeleton::ConduitType;

    let cell = (scale * 4.0).ceil() as usize;
    let kinds = ConduitType::ALL;
    let (top, name_h) = (40.0, 22.0);
    let bottom = top + name_h + cell as f64;
    let mut canvas = Canvas::new((cell * kinds.len()) as u32, (bottom + 30.0) as u32, [250, 250, 250]);
    let title = format!(
        "Cross-sections at radius 1 m, ratio {}, asymmetry {}",
        ticks::human(ratio),
        ticks::human(asymmetry)
    );
    text::draw(&mut canvas, &title, (8.0, 8.0), TITLE, Align::Left, Valign::Top);
    let shape = Shape { radius: 1.0, ratio: ratio as f32, asymmetry: asymmetry as f32 };
    for (k, kind) in kinds.into_iter().enumerate() {
        let section = Section::of(kind, shape);
        for y in 0..cell {
            for x in 0..cell {
                let q =
                    glam::DVec2::new(x as f64 + 0.5 - cell as f64 / 2.0, cell as f64 / 2.0 - y as f64 - 0.5)
                        / scale;
                let d = section.distance(q);
                let colour = if d.abs() < 1.0 / scale {
                    OUTLINE
                } else if d < 0.0 {
                    CAVE_AIR
                } else {
                    [170, 170, 160]
                };
                canvas.set((k * cell + x) as i64, (top + name_h) as i64 + y as i64, colour);
            }
        }
        let centre = ((k * cell) as f64 + cell as f64 / 2.0, top + name_h / 2.0);
        text::draw(&mut canvas, kind.name(), centre, SMALL, Align::Centre, Valign::Middle);
    }
    let bar = Rect::at(8.0, bottom + 12.0, scale, 6.0);
    canvas.fill_rect(bar, CAVE_AIR);
    text::draw(&mut canvas, "1 m", (bar.x1 + 6.0, bar.y0 + 3.0), SMALL, Align::Left, Valign::Middle);
    canvas
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::{SdfView, synthetic};
    use karst_scene::{Scene, SceneView};

    fn field() -> CarvedTerrain {
        let (skeleton, hydro) = synthetic::network(3, 6, 8);
        let scene = Scene::parse(synthetic::SCENE, std::path::Path::new("synthetic.toml")).unwrap();
        CarvedTerrain::new(crate::build::build(&SdfView::of(&scene), &skeleton, &hydro).unwrap())
    }

    #[test]
    fn a_slice_is_drawn_on_axes_with_its_key() {
        let field = field();
        let grid = SliceGrid::new(&field, Plane::Z(100.0), 4.0, None);
        assert_eq!((grid.width, grid.height), (250, 250));
        let canvas = picture(&field, &grid);
        // Enlarged ×1 (250 px < 480 px needs ×1.92, rounded down), framed at x = LEFT.
        assert!(canvas.width() as f64 > axes::LEFT + 250.0 + 100.0);
        assert!(canvas.height() as f64 >= 44.0 + 250.0 + axes::BOTTOM);
        let mut bytes = Vec::new();
        canvas.encode_png(&mut bytes).unwrap();
        let (w, h, colours) = karst_plot::testing::png_summary(&bytes);
        assert_eq!((w, h), (canvas.width(), canvas.height()));
        assert!(colours > 20, "{colours} colours");
    }

    #[test]
    fn the_rock_key_spans_the_shades_used() {
        let bar = rock_bar();
        assert_eq!(colour(Cell::Rock(0.0), &bar), [170, 170, 160]);
        assert_eq!(colour(Cell::Rock(DEEP_ROCK * 3.0), &bar), [90, 90, 80]);
        assert_eq!(bar.ticks(160.0).last(), Some(&DEEP_ROCK));
    }

    /// A round conduit of radius 3 m along y through the origin, water 0.3 m deep on its floor.
    struct Stream;

    impl Fields for Stream {
        fn rock(&self, p: DVec3) -> f64 {
            -self.cave(p)
        }

        fn cave(&self, p: DVec3) -> f64 {
            p.x.hypot(p.z) - 3.0
        }

        fn water(&self, p: DVec3) -> f64 {
            self.cave(p).max((p.z + 2.85).abs() - 0.15)
        }
    }

    fn across_the_stream(pixel: f64) -> SliceGrid {
        let size = (10.0 / pixel).round() as usize;
        SliceGrid { width: size, height: size, u0: -5.0, v1: 5.0, plane: Plane::Y(0.0), pixel }
    }

    #[test]
    fn water_thinner_than_the_pixel_is_found_and_noted() {
        let count = |pixel: f64, class: Cell| {
            cells(&Stream, &across_the_stream(pixel)).iter().filter(|c| **c == class).count()
        };
        // 1 m pixels: centres at z = −2.5 and −3.5 miss the water between −3 and −2.7.
        assert_eq!(count(1.0, Cell::Water), 0);
        assert!(count(1.0, Cell::ThinWater) > 0);
        // 5 cm pixels: six rows of water, and no pixel of it is taken for thin water.
        assert!(count(0.05, Cell::Water) > 100);
        assert_eq!(count(0.05, Cell::ThinWater), 0);
        assert_eq!(thin_water_note(0, 1.0), None);
        assert!(thin_water_note(3, 1.0).unwrap().contains("the 1 m pixel: 3 pixel(s)"));
    }

    #[test]
    fn sections_picture_has_one_cell_per_type() {
        let c = sections_picture(1.0, 0.2, 40.0);
        assert_eq!(c.width(), 160 * 7);
        assert!(!c.is_blank());
    }
}
