//! karst-plot: every picture karstgen draws (network renders, SDF slices, metric plots, mesh
//! previews, ensemble maps) is drawn with this crate, so that they share one look: anti-aliased
//! shapes (tiny-skia), real text in DejaVu Sans (embedded, rasterised from its outlines via
//! ab_glyph, no system fonts), axes with units and ticks at round numbers, legends, colour
//! bars, labels that do not collide, histogram classes chosen for the data, and map furniture
//! (scale bar, north arrow). Pictures are deterministic: the same input gives the same PNG bytes.
//!
//! - [`canvas`]: the RGB picture, shapes, pixels, PNG output;
//! - [`text`]: the font, measuring and drawing text;
//! - [`ticks`]: nice steps and numbers rounded for people;
//! - [`axes`]: a data window in a frame with ticks and titles;
//! - [`legend`], [`colour_bar`]: keys to colours;
//! - [`bins`]: histogram classes (Freedman–Diaconis, Sturges for few values);
//! - [`labels`]: collision-free placement of point labels;
//! - [`map`]: scale bar and north arrow;
//! - [`network`]: the top-and-side picture of a conduit network.

pub mod axes;
pub mod bins;
pub mod canvas;
pub mod colour_bar;
pub mod labels;
pub mod legend;
pub mod map;
pub mod network;
pub mod text;
pub mod ticks;

pub use canvas::{BLACK, Canvas, GREY, INK, LIGHT_GREY, Point, Rect, Rgb, WHITE};
#[cfg(any(test, feature = "testing"))]
pub mod testing;
