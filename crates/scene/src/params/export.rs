//! `[export]`: which files the export stage writes for other tools (docs/exports.md), and the
//! options of those files.
//!
//! The default formats are the cheap ones: the network in every format and one glTF scene
//! (terrain, cave, water, network). The large mesh files (OBJ, PLY, VTK and GOCAD TSurf
//! meshes, hundreds of MB on the big presets) are written only when listed.

use serde::{Deserialize, Serialize};

use crate::validate::Checks;

/// One export format.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum ExportFormat {
    /// The network as VTK XML PolyData (`network.vtp`, ParaView).
    Vtk,
    /// The meshes as VTK XML PolyData (`terrain.vtp`, `cave.vtp`, `water.vtp`).
    VtkMeshes,
    /// The network as a GOCAD PLine and the samples as a GOCAD VSet.
    Gocad,
    /// The meshes as GOCAD TSurfs.
    GocadMeshes,
    /// The conduit centrelines as a Survex survey (`network.svx`).
    Survex,
    /// The network as an EPA SWMM 5 model (`network.inp`).
    Swmm,
    /// One binary glTF scene: the meshes and the network (`karst.glb`).
    Gltf,
    /// The meshes as Wavefront OBJ.
    Obj,
    /// The meshes as binary PLY.
    Ply,
    /// The network's node and segment tables and the metrics as CSV.
    Csv,
    /// The network, key points, surface streams and routes as an OGC GeoPackage
    /// (`karst.gpkg`, QGIS and ArcGIS); written whenever the scene has a `crs`.
    Gpkg,
    /// Rasters of the conduits' depth and density as GeoTIFFs (`conduit-depth.tif`,
    /// `conduit-density.tif`); written whenever the scene has a `crs`.
    Geotiff,
}

impl ExportFormat {
    /// Every format, in the order they are written.
    pub const ALL: [ExportFormat; 12] = [
        ExportFormat::Vtk,
        ExportFormat::VtkMeshes,
        ExportFormat::Gocad,
        ExportFormat::GocadMeshes,
        ExportFormat::Survex,
        ExportFormat::Swmm,
        ExportFormat::Gltf,
        ExportFormat::Obj,
        ExportFormat::Ply,
        ExportFormat::Csv,
        ExportFormat::Gpkg,
        ExportFormat::Geotiff,
    ];

    /// The name used in the scene and on the command line.
    pub fn name(self) -> &'static str {
        match self {
            ExportFormat::Vtk => "vtk",
            ExportFormat::VtkMeshes => "vtk-meshes",
            ExportFormat::Gocad => "gocad",
            ExportFormat::GocadMeshes => "gocad-meshes",
            ExportFormat::Survex => "survex",
            ExportFormat::Swmm => "swmm",
            ExportFormat::Gltf => "gltf",
            ExportFormat::Obj => "obj",
            ExportFormat::Ply => "ply",
            ExportFormat::Csv => "csv",
            ExportFormat::Gpkg => "gpkg",
            ExportFormat::Geotiff => "geotiff",
        }
    }

    /// Parses a format name.
    pub fn from_name(name: &str) -> Option<ExportFormat> {
        ExportFormat::ALL.into_iter().find(|f| f.name() == name)
    }
}

/// One of the meshed surfaces.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum MeshSurface {
    Terrain,
    Cave,
    Water,
}

#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct ExportParams {
    /// The formats to write.
    pub formats: Vec<ExportFormat>,
    /// The surfaces the mesh formats carry (glTF, OBJ, PLY, VTK and TSurf meshes).
    pub surfaces: Vec<MeshSurface>,
    /// Manning's roughness n of every conduit of the SWMM model, s/m^(1/3). The default 0.03 is
    /// a rough natural channel; for a full pipe of radius r it is the Darcy–Weisbach friction
    /// factor f = 8 g n² / (r/2)^(1/3) ≈ 0.09 at r = 1 m, within the range measured in cave
    /// conduits (Jeannin 2001). It is the first thing a modeller calibrates.
    pub manning: f64,
    /// Simulated time of the SWMM model, hours: long enough for the constant inflows to reach
    /// a steady state.
    pub swmm_hours: f64,
    /// Steepest conduit slope of the SWMM model (drop over length). Steeper segments (shafts)
    /// keep this slope and drop the rest at their lower junction, as drop structures are
    /// modelled in SWMM: its dynamic-wave solver is not made for near-vertical conduits.
    pub swmm_max_slope: f64,
    /// Shortest conduit of the SWMM model, metres: chains of segments between the nodes where
    /// conduits meet, water enters or leaves, or waters divide are merged into conduits at
    /// least this long (a whole chain when it is shorter), as modellers skeletonize a network
    /// for the dynamic-wave solver's time step.
    pub swmm_conduit_length: f64,
    /// Pixel size of the GeoTIFF rasters, metres, when the terrain is no raster (a plane or
    /// noise); a GeoTIFF or heightfield terrain gives its own grid. Default: the domain's
    /// longer horizontal side / 500, about a metre for a 500 m cave system.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub raster_cell: Option<f64>,
    /// Largest size of `karst.glb`, MB (MiB), default [`DEFAULT_GLTF_MB`]: a file for viewers,
    /// whose surfaces are simplified to the triangles that fit (docs/exports.md).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub gltf_max_mb: Option<f64>,
    /// `karst.glb` at the mesher's full resolution, whatever its size (an archive, not a file
    /// for viewers).
    #[serde(default, skip_serializing_if = "std::ops::Not::not")]
    pub gltf_full: bool,
}

/// The default bound of `karst.glb`, MB (MiB).
pub const DEFAULT_GLTF_MB: f64 = 100.0;

impl Default for ExportParams {
    fn default() -> Self {
        ExportParams {
            formats: vec![
                ExportFormat::Vtk,
                ExportFormat::Gocad,
                ExportFormat::Survex,
                ExportFormat::Swmm,
                ExportFormat::Gltf,
                ExportFormat::Csv,
            ],
            surfaces: vec![MeshSurface::Terrain, MeshSurface::Cave, MeshSurface::Water],
            manning: 0.03,
            swmm_hours: 6.0,
            swmm_max_slope: 0.1,
            swmm_conduit_length: 20.0,
            raster_cell: None,
            gltf_max_mb: None,
            gltf_full: false,
        }
    }
}

impl ExportParams {
    /// The bound of `karst.glb`, bytes; `None` when it is written at full resolution.
    pub fn gltf_bound(&self) -> Option<f64> {
        (!self.gltf_full).then(|| self.gltf_max_mb.unwrap_or(DEFAULT_GLTF_MB) * crate::budget::MB)
    }

    pub(crate) fn check(&self, c: &mut Checks) {
        c.positive("export.manning", self.manning);
        c.positive("export.swmm_hours", self.swmm_hours);
        c.positive("export.swmm_max_slope", self.swmm_max_slope);
        c.positive("export.swmm_conduit_length", self.swmm_conduit_length);
        if let Some(cell) = self.raster_cell {
            c.positive("export.raster_cell", cell);
        }
        if let Some(mb) = self.gltf_max_mb {
            c.positive("export.gltf_max_mb", mb);
        }
        if self.swmm_hours.is_finite() && self.swmm_hours > 24.0 * 365.0 {
            c.report("export.swmm_hours", format!("{} hours is more than a year", self.swmm_hours));
        }
    }
}

#[cfg(test)]
mod tests {
    use std::path::Path;

    use super::*;
    use crate::{Scene, SceneError};

    const SCENE: &str = "name = \"t\"\n[domain]\nmin = [0, 0, 0]\nmax = [100, 100, 50]\n\
        [terrain]\nkind = \"plane\"\nelevation = 40\n[[geology.water_tables]]\nname = \"wt\"\nelevation = 10\n\
        [[keypoints]]\nname = \"a\"\nkind = \"sink\"\nposition = [10, 10, 40]\n\
        [[keypoints]]\nname = \"s\"\nkind = \"spring\"\nposition = [90, 90, 10]\nwater_table = \"wt\"\n";

    fn parse(export: &str) -> Result<Scene, Vec<String>> {
        match Scene::parse(&format!("{SCENE}[export]\n{export}\n"), Path::new("s.toml")) {
            Ok(scene) => Ok(scene),
            Err(SceneError::Invalid { problems, .. }) => {
                Err(problems.iter().map(|p| p.to_string()).collect())
            }
            Err(e) => Err(vec![e.to_string()]),
        }
    }

    #[test]
    fn defaults_are_the_cheap_formats() {
        let scene = parse("").unwrap();
        assert_eq!(scene.export, ExportParams::default());
        assert!(!scene.export.formats.contains(&ExportFormat::Obj));
        let scene = parse("formats = [\"obj\", \"vtk-meshes\"]\nsurfaces = [\"cave\"]").unwrap();
        assert_eq!(scene.export.formats, [ExportFormat::Obj, ExportFormat::VtkMeshes]);
        assert_eq!(scene.export.surfaces, [MeshSurface::Cave]);
        for f in ExportFormat::ALL {
            assert_eq!(ExportFormat::from_name(f.name()), Some(f));
        }
    }

    #[test]
    fn unknown_formats_and_bad_values_name_the_field() {
        let p = parse("formats = [\"vtk\", \"shapefile\"]").unwrap_err();
        assert!(
            p[0].contains(":21:") && p[0].contains("export.formats") && p[0].contains("shapefile"),
            "{p:?}"
        );
        let p = parse("gltf_max_mb = -1").unwrap_err();
        assert!(p.iter().any(|m| m.contains("export.gltf_max_mb")), "{p:?}");
        let p = parse("manning = 0\nswmm_hours = nan").unwrap_err();
        assert!(p.iter().any(|m| m.contains("export.manning: must be > 0, got 0")), "{p:?}");
        assert!(p.iter().any(|m| m.contains("export.swmm_hours")), "{p:?}");
    }
}
