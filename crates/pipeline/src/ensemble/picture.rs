//! The pictures of the probability grid: one EXR image per horizontal slice of cells
//! (`probability/z-NNN.exr`, one float channel `P`) and the top view `probability-top.png`, the
//! fraction of realizations with a conduit anywhere in each column of cells, as a map.

use karst_plot::axes::{self, Axes};
use karst_plot::colour_bar::{BAR_WIDTH, ColourBar, ColourMap};
use karst_plot::text::{self, Align, Valign};
use karst_plot::{Canvas, Rect, WHITE, ticks};

use super::grid::Grid;

/// One slice as an EXR image: one float channel `P`, scanlines from y = 0 (south) up,
/// ZIP-compressed, encoded serially.
pub(super) fn exr_slice(width: usize, height: usize, values: &[f32]) -> Result<Vec<u8>, exr::error::Error> {
    use exr::prelude::*;
    let pixels = SpecificChannels::build()
        .with_channel("P")
        .with_pixel_fn(|p: Vec2<usize>| (values[p.1 * width + p.0],));
    let mut bytes = std::io::Cursor::new(Vec::new());
    Image::from_encoded_channels((width, height), Encoding::SMALL_LOSSLESS, pixels)
        .write()
        .non_parallel()
        .to_buffered(&mut bytes)?;
    Ok(bytes.into_inner())
}

/// The top-view probability as a map: cells on axes in metres (north up), a colour bar, a
/// scale bar and a north arrow.
pub(super) fn top_view(grid: &Grid, probabilities: &[f64], n: usize) -> Canvas {
    let [nx, ny, _] = grid.dims;
    let zoom = (600 / nx.max(ny)).max(1) as f64;
    let frame = Rect::at(axes::LEFT, 64.0, nx as f64 * zoom, ny as f64 * zoom);
    let bar = probability_bar();
    let bar_box =
        Rect::at(frame.x1 + 24.0, frame.y0 + ColourBar::title_height(), BAR_WIDTH, frame.height().min(240.0));
    let extent = |a: usize| (grid.min[a], grid.min[a] + grid.dims[a] as f64 * grid.cell);
    let map = Axes::new(frame, extent(0), extent(1));
    let furniture_at = (bar_box.x0, bar_box.y1 + 20.0);
    let (furniture_w, furniture_h) = karst_plot::map::panel_size(&map);
    let width = bar_box.x0 + bar.width(bar_box.height()).max(furniture_w) + 16.0;
    let height = (frame.y1 + axes::BOTTOM + 8.0).max(furniture_at.1 + furniture_h + 8.0);
    let mut c = Canvas::new(width.ceil() as u32, height.ceil() as u32, WHITE);
    for iy in 0..ny {
        for ix in 0..nx {
            let (x0, y0) = (frame.x0 + ix as f64 * zoom, frame.y0 + (ny - 1 - iy) as f64 * zoom);
            c.fill_rect(Rect::at(x0, y0, zoom, zoom), bar.colour(probabilities[iy * nx + ix]));
        }
    }
    karst_plot::map::draw_panel(&mut c, &map, furniture_at);
    map.draw(&mut c, "easting x (m)", "northing y (m)");
    bar.draw(&mut c, bar_box);
    let title = format!("Conduit probability of {n} realizations, {} m cells", ticks::human(grid.cell));
    text::draw(&mut c, &title, (axes::LEFT, 10.0), text::TITLE, Align::Left, Valign::Top);
    let caption = "fraction of realizations with a conduit anywhere in each column of cells (white: none)";
    text::draw(&mut c, caption, (axes::LEFT, 36.0), text::SMALL, Align::Left, Valign::Top);
    c
}

/// White at 0, then pale yellow through orange to dark red at 1.
fn probability_bar() -> ColourBar {
    ColourBar {
        map: ColourMap::new(&[(0.0, WHITE), (1e-9, [255, 230, 120]), (1.0, [130, 0, 20])]),
        range: (0.0, 1.0),
        title: "fraction of realizations".into(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_probability_map_decodes_at_its_size() {
        let grid = Grid { min: [0.0; 3], cell: 10.0, dims: [30, 20, 4] };
        let p: Vec<f64> = (0..600).map(|i| f64::from(i % 7) / 6.0).collect();
        let canvas = top_view(&grid, &p, 6);
        let mut bytes = Vec::new();
        canvas.encode_png(&mut bytes).unwrap();
        let (w, h, colours) = karst_plot::testing::png_summary(&bytes);
        // 20 px per cell: a 600 × 400 px map under the title, axes below it.
        assert_eq!(h, (64.0 + 400.0 + axes::BOTTOM + 8.0) as u32);
        assert!(w > 600 + axes::LEFT as u32 && colours > 10, "{w} px, {colours} colours");
        assert_eq!(canvas.get(axes::LEFT as i64 + 5, 64 + 395), Some(probability_bar().colour(0.0)));
    }
}
