//! Stage 9: exports of a run into the formats other tools read, each file checked in the test
//! suite by the tool it targets (docs/exports.md). [`ExportStage`] is the stage: it writes the
//! scene's `[export]` formats and records them in `export.json` ([`Manifest`], `payload.rs`);
//! `karstgen export DIR --format …` (and `karst-export DIR`) writes any formats on demand.
//!
//! [`export`] writes the formats of an `ExportParams` (the scene's `[export]` section) into
//! `DIR/export/` and returns the [`Manifest`] of what it wrote. It reads nothing itself: the
//! upstream payloads come in an [`Inputs`], and a format whose input is missing is refused
//! before any file is written. Every file is written atomically and hashed as it streams out.
//!
//! One id convention in every table a user sees: network nodes, segments and conduits are
//! numbered from 1 (node `i` of skeleton.json is node `i + 1`), as karstnet's `.dat` files
//! require; SWMM junction names, Survex station names, GOCAD vertex properties and CSV id
//! columns all use it. Every coordinate goes through one [`frame::Frame`], so that a world
//! origin can be added in one place.
//!
//! Modules: `network.rs` derives the per-node and per-segment attributes every network format
//! shares, `surface.rs` the codes and names of the surface streams' categories (streams.json,
//! written by VTK as `streams.vtp` and by CSV as `stream_nodes.csv`, `stream_segments.csv`);
//! one module per format (`vtk.rs`, `gocad.rs`, `survex.rs`, `swmm.rs`, `gltf.rs`,
//! `obj.rs`, `ply.rs`, `csv.rs`, `gpkg/` for the GeoPackage, `geotiff.rs` for the rasters
//! that `rasters.rs` computes from the conduits' footprints, `footprint.rs`); `folder.rs` writes
//! and records the files; `frame.rs` places every coordinate. A scene with a `crs` always gets
//! the GIS formats (`karst.gpkg` and the GeoTIFF rasters, [`formats`]).

mod build;
mod csv;
mod error;
pub mod estimate;
mod folder;
pub mod footprint;
pub mod frame;
pub mod geotiff;
mod gltf;
mod gocad;
pub mod gpkg;
mod network;
mod obj;
mod payload;
mod ply;
pub mod rasters;
pub mod stage;
mod surface;
mod survex;
mod swmm;
mod view;
mod vtk;

pub use build::{FOLDER, Input, Inputs, export, formats, needs};
pub use error::ExportError;
pub use karst_scene::params::{ExportFormat, ExportParams, MeshSurface};
pub use network::NetworkView;
pub use payload::{ExportedFile, Manifest};
pub use stage::ExportStage;
pub use view::ExportView;
