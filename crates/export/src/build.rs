//! The export's entry: which upstream artifacts each format reads, and writing the chosen
//! formats into `DIR/export/`.

use std::path::Path;

use karst_geology::{Domain, Geology, Terrain};
use karst_hydro::Hydro;
use karst_mesher::Mesh;
use karst_metrics::MetricsReport;
use karst_sampling::Samples;
use karst_scene::KeyPoint;
use karst_scene::params::{ExportFormat, ExportParams};
use karst_skeleton::Skeleton;
use karst_streams::Streams;

use crate::error::ExportError;
use crate::folder::{self, Folder};
use crate::frame::Frame;
use crate::network::NetworkView;
use crate::payload::Manifest;
use crate::{csv, geotiff, gltf, gocad, gpkg, obj, ply, rasters, survex, swmm, vtk};

/// Name of the export folder inside the output folder.
pub const FOLDER: &str = "export";

/// The upstream payloads an export may read; each format says which it needs.
#[derive(Debug, Clone, Copy)]
pub struct Inputs<'a> {
    pub skeleton: Option<&'a Skeleton>,
    pub hydro: Option<&'a Hydro>,
    pub streams: Option<&'a Streams>,
    pub mesh: Option<&'a Mesh>,
    pub metrics: Option<&'a MetricsReport>,
    pub samples: Option<&'a Samples>,
    /// The scene's geology, for what the artifacts do not carry (the rock layer of each sample).
    pub geology: Option<&'a Geology>,
    /// The scene's key points, terrain and domain (local coordinates), for the GIS formats.
    pub keypoints: Option<&'a [KeyPoint]>,
    pub terrain: Option<&'a Terrain>,
    pub domain: Option<&'a Domain>,
    /// The local frame the artifacts are in (the origin exports add back, the CRS).
    pub frame: &'a karst_artifact::Frame,
}

/// An upstream artifact a format reads.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord)]
pub enum Input {
    Skeleton,
    Hydro,
    Streams,
    Mesh,
    Metrics,
    Samples,
    /// The scene itself (its key points, terrain and domain).
    Scene,
}

impl Input {
    /// The artifact's file name in the output folder.
    pub fn file_name(self) -> &'static str {
        match self {
            Input::Skeleton => "skeleton.json",
            Input::Hydro => "hydro.json",
            Input::Streams => "streams.json",
            Input::Mesh => "mesh.bin",
            Input::Metrics => "metrics.json",
            Input::Samples => "samples.bin",
            Input::Scene => "the scene file",
        }
    }

    fn present(self, inputs: &Inputs) -> bool {
        match self {
            Input::Skeleton => inputs.skeleton.is_some(),
            Input::Hydro => inputs.hydro.is_some(),
            Input::Streams => inputs.streams.is_some(),
            Input::Mesh => inputs.mesh.is_some(),
            Input::Metrics => inputs.metrics.is_some(),
            Input::Samples => inputs.samples.is_some(),
            Input::Scene => inputs.keypoints.is_some() && inputs.terrain.is_some() && inputs.domain.is_some(),
        }
    }
}

/// The artifacts `format` reads. VTK and CSV carry the surface streams beside the conduits;
/// the other network formats are the underground network alone (docs/exports.md).
pub fn needs(format: ExportFormat) -> &'static [Input] {
    match format {
        ExportFormat::Vtk => &[Input::Skeleton, Input::Hydro, Input::Streams],
        ExportFormat::Survex | ExportFormat::Swmm => &[Input::Skeleton, Input::Hydro],
        ExportFormat::Gocad => &[Input::Skeleton, Input::Hydro, Input::Samples],
        ExportFormat::VtkMeshes | ExportFormat::GocadMeshes | ExportFormat::Obj | ExportFormat::Ply => {
            &[Input::Mesh]
        }
        ExportFormat::Gltf => &[Input::Skeleton, Input::Hydro, Input::Mesh],
        ExportFormat::Csv => &[Input::Skeleton, Input::Hydro, Input::Streams, Input::Metrics],
        ExportFormat::Gpkg => &[Input::Skeleton, Input::Hydro, Input::Streams, Input::Scene],
        ExportFormat::Geotiff => &[Input::Skeleton, Input::Hydro, Input::Scene],
    }
}

/// The formats written: those of `params`, and the GIS formats (GeoPackage and GeoTIFF
/// rasters) whenever the run has a CRS; sorted, each once.
pub fn formats(params: &ExportParams, frame: &karst_artifact::Frame) -> Vec<ExportFormat> {
    let mut formats = params.formats.clone();
    if frame.crs.is_some() {
        formats.extend([ExportFormat::Gpkg, ExportFormat::Geotiff]);
    }
    formats.sort();
    formats.dedup();
    formats
}

/// Writes the formats of `params` into `dir/export/` and returns what was written.
pub fn export(inputs: &Inputs, params: &ExportParams, dir: &Path) -> Result<Manifest, ExportError> {
    let formats = formats(params, inputs.frame);
    for &format in &formats {
        match needs(format).iter().find(|i| !i.present(inputs)) {
            Some(Input::Scene) => {
                return Err(ExportError::Unsupported(format!(
                    "format `{}` needs the scene (its key points, terrain and domain): give --scene SCENE",
                    format.name()
                )));
            }
            Some(missing) => {
                return Err(ExportError::MissingInput { format: format.name(), input: missing.file_name() });
            }
            None => {}
        }
    }
    let frame = Frame::of(inputs);
    let network = match (inputs.skeleton, inputs.hydro) {
        (Some(skeleton), Some(hydro)) => Some(NetworkView::new(skeleton, hydro)?),
        _ => None,
    };
    let surfaces = inputs.mesh.map(|mesh| folder::Surfaces::new(mesh, &params.surfaces, &params.formats));
    let mut folder = Folder::create(&dir.join(FOLDER))?;
    for format in formats {
        let network = || network.as_ref().expect("network formats need skeleton and hydro");
        let surfaces = || surfaces.as_ref().expect("mesh formats need the mesh");
        match format {
            ExportFormat::Vtk => {
                vtk::write_network(&mut folder, &frame, network())?;
                vtk::write_streams(&mut folder, &frame, inputs.streams.expect("checked above"))?;
            }
            ExportFormat::VtkMeshes => vtk::write_meshes(&mut folder, &frame, surfaces())?,
            ExportFormat::Gocad => {
                gocad::write_pline(&mut folder, &frame, network())?;
                let samples = inputs.samples.expect("checked above");
                gocad::write_vset(&mut folder, &frame, samples, inputs.geology)?;
            }
            ExportFormat::GocadMeshes => gocad::write_tsurfs(&mut folder, &frame, surfaces())?,
            ExportFormat::Survex => survex::write(&mut folder, &frame, network())?,
            ExportFormat::Swmm => swmm::write(&mut folder, &frame, network(), params)?,
            ExportFormat::Gltf => {
                gltf::write(&mut folder, &frame, surfaces(), network(), params.gltf_bound())?
            }
            ExportFormat::Obj => obj::write(&mut folder, &frame, surfaces())?,
            ExportFormat::Ply => ply::write(&mut folder, &frame, surfaces())?,
            ExportFormat::Csv => {
                csv::write(&mut folder, &frame, network(), inputs.metrics.expect("checked above"))?;
                csv::write_streams(&mut folder, &frame, inputs.streams.expect("checked above"))?;
            }
            ExportFormat::Gpkg => {
                let sources = gpkg::layers::Sources {
                    frame: &frame,
                    net: network(),
                    skeleton: inputs.skeleton.expect("checked above"),
                    streams: inputs.streams.expect("checked above"),
                    keypoints: inputs.keypoints.expect("checked above"),
                };
                let srs = gpkg::Srs::of(inputs.frame.crs.as_deref())?;
                gpkg::write(&mut folder, &srs, &gpkg::layers::all(&sources))?;
            }
            ExportFormat::Geotiff => {
                let terrain = inputs.terrain.expect("checked above");
                let grid = rasters::RasterGrid::of(
                    terrain,
                    inputs.domain.expect("checked above"),
                    params.raster_cell,
                )?;
                let maps = rasters::ConduitMaps::of(&grid, terrain, network());
                let crs = geotiff::Crs::of(inputs.frame.crs.as_deref())?;
                let place = geotiff::Placement::of(&grid, &frame, crs);
                geotiff::write(&mut folder, "conduit-depth.tif", &place, &maps.depth)?;
                geotiff::write(&mut folder, "conduit-density.tif", &place, &maps.density)?;
            }
        }
    }
    Ok(folder.finish())
}
