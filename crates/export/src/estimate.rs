//! The export's work said before it runs: the bytes of each format from the counts of what it
//! writes (network nodes and segments, samples, surface-stream segments, the chosen surfaces'
//! vertices and triangles), so that a run can hold them against its output budget before a
//! file is written (crates/pipeline/src/budget.rs, docs/limits.md).
//!
//! Each format costs a fixed header plus bytes per item, the sizes of its records (binary
//! formats) or of their typical text lines (text formats). `karst.glb` costs at most its bound
//! (`export.gltf_max_mb`): larger surfaces are simplified to fit. The GIS rasters count one
//! float per pixel before compression (an upper bound: the rasters are mostly no-data).

use std::fmt;

use karst_mesher::Mesh;
use karst_sampling::Samples;
use karst_scene::budget::bytes;
use karst_scene::params::{ExportFormat, ExportParams, MeshSurface};
use karst_skeleton::Skeleton;
use karst_streams::Streams;

/// Bytes of a header, a document, or the fixed tables of a file.
const HEADER: f64 = 4096.0;
/// The GeoPackage's fixed tables (SQLite pages, spatial reference systems, styles).
const GPKG_TABLES: f64 = 262_144.0;
/// Pixels of each GeoTIFF raster along the domain's longer side when none is given.
const RASTER_SIDE: f64 = 500.0;

/// The counts the exports' sizes follow.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct Counts {
    pub nodes: f64,
    pub segments: f64,
    pub samples: f64,
    pub stream_segments: f64,
    /// Vertices and triangles of the chosen surfaces (`export.surfaces`).
    pub vertices: f64,
    pub triangles: f64,
}

impl Counts {
    /// The counts of the given payloads (a missing one counts nothing).
    pub fn of(
        skeleton: Option<&Skeleton>,
        samples: Option<&Samples>,
        streams: Option<&Streams>,
        mesh: Option<&Mesh>,
        surfaces: &[MeshSurface],
    ) -> Counts {
        let (mut vertices, mut triangles) = (0.0, 0.0);
        if let Some(mesh) = mesh {
            for (which, surface) in [
                (MeshSurface::Terrain, &mesh.terrain),
                (MeshSurface::Cave, &mesh.cave),
                (MeshSurface::Water, &mesh.water),
            ] {
                if surfaces.contains(&which) {
                    vertices += surface.vertices.len() as f64;
                    triangles += surface.triangles.len() as f64;
                }
            }
        }
        Counts {
            nodes: skeleton.map_or(0, |s| s.nodes.len()) as f64,
            segments: skeleton.map_or(0, |s| s.conduits.iter().map(|c| c.nodes.len().saturating_sub(1)).sum())
                as f64,
            samples: samples.map_or(0, |s| s.positions.len()) as f64,
            stream_segments: streams.map_or(0, |s| s.segments.len()) as f64,
            vertices,
            triangles,
        }
    }
}

/// Bytes of `format`'s files for `counts`; `raster_pixels` the pixels of one GIS raster.
pub fn format_bytes(format: ExportFormat, c: &Counts, params: &ExportParams, raster_pixels: f64) -> f64 {
    let mesh = |per_vertex: f64, per_triangle: f64| {
        3.0 * HEADER + per_vertex * c.vertices + per_triangle * c.triangles
    };
    match format {
        ExportFormat::Vtk => 2.0 * HEADER + 70.0 * (c.nodes + c.segments) + 100.0 * c.stream_segments,
        ExportFormat::VtkMeshes => mesh(36.0, 16.0),
        ExportFormat::Gocad => 2.0 * HEADER + 140.0 * c.nodes + 75.0 * c.samples,
        ExportFormat::GocadMeshes => mesh(50.0, 20.0),
        ExportFormat::Survex => HEADER + 60.0 * c.segments,
        ExportFormat::Swmm => HEADER + 40.0 * (c.nodes + c.segments),
        ExportFormat::Gltf => {
            let full = HEADER + 24.0 * c.vertices + 12.0 * c.triangles + 12.0 * c.nodes + 8.0 * c.segments;
            params.gltf_bound().map_or(full, |bound| full.min(bound))
        }
        ExportFormat::Obj => mesh(70.0, 40.0),
        ExportFormat::Ply => mesh(36.0, 13.0),
        ExportFormat::Csv => 2.0 * HEADER + 105.0 * c.nodes + 115.0 * c.segments + 150.0 * c.stream_segments,
        ExportFormat::Gpkg => GPKG_TABLES + 400.0 * (c.segments + c.stream_segments),
        ExportFormat::Geotiff => 2.0 * (HEADER + 4.0 * raster_pixels),
    }
}

/// What an export would write, said before a file is: the bytes of each chosen format, and
/// beside them the bytes of the run's mesh.bin, which the output budget counts with them.
#[derive(Debug, Clone, PartialEq)]
pub struct Estimate {
    pub formats: Vec<(ExportFormat, f64)>,
    pub mesh_bytes: f64,
}

impl Estimate {
    /// The bytes of `formats` for `counts` (`raster_pixels` the pixels of one GIS raster),
    /// beside `mesh_bytes` of mesh.bin.
    pub fn of(
        formats: &[ExportFormat],
        counts: &Counts,
        params: &ExportParams,
        raster_pixels: f64,
        mesh_bytes: f64,
    ) -> Estimate {
        let formats = formats.iter().map(|&f| (f, format_bytes(f, counts, params, raster_pixels))).collect();
        Estimate { formats, mesh_bytes }
    }

    /// Bytes of the exports.
    pub fn exports(&self) -> f64 {
        self.formats.iter().map(|(_, b)| b).sum()
    }

    /// Bytes of the exports and of mesh.bin, which the output budget holds together.
    pub fn total(&self) -> f64 {
        self.exports() + self.mesh_bytes
    }
}

impl fmt::Display for Estimate {
    /// `about 5.03 MiB of exports (gltf 4.83 MiB, csv 12.0 KiB) beside 2.77 MiB of mesh.bin`.
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let list: Vec<String> =
            self.formats.iter().map(|(format, b)| format!("{} {}", format.name(), bytes(*b))).collect();
        write!(
            f,
            "about {} of exports ({}) beside {} of mesh.bin",
            bytes(self.exports()),
            list.join(", "),
            bytes(self.mesh_bytes)
        )
    }
}

/// Pixels of one GIS raster over a domain of horizontal `extent` metres, `cell` metres a pixel
/// (default: the longer side over [`RASTER_SIDE`]).
pub fn raster_pixels(extent: [f64; 2], cell: Option<f64>) -> f64 {
    let cell = cell.unwrap_or(extent[0].max(extent[1]) / RASTER_SIDE);
    (extent[0] / cell).ceil() * (extent[1] / cell).ceil()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_glb_costs_at_most_its_bound_unless_full_is_asked() {
        let c = Counts { vertices: 1e7, triangles: 2e7, ..Counts::default() };
        let bounded = ExportParams::default();
        assert_eq!(format_bytes(ExportFormat::Gltf, &c, &bounded, 0.0), 100.0 * (1u64 << 20) as f64);
        let full = ExportParams { gltf_full: true, ..ExportParams::default() };
        assert!(format_bytes(ExportFormat::Gltf, &c, &full, 0.0) > 4e8);
        assert_eq!(raster_pixels([1000.0, 500.0], None), 500.0 * 250.0);
    }
}
