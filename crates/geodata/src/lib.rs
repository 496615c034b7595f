//! Geodata readers: the files a scene names, turned from bytes into raw grids, points,
//! triangles and coordinate reference systems, before anything gives them a geological meaning
//! (that is `karst-geology`) or checks them against a scene (that is `karst-scene`).
//!
//! GeoTIFF rasters with their GeoKeys ([`geotiff`], [`geokeys`]), heightfield images (PNG,
//! OpenEXR: [`image`]), EPSG codes ([`crs`]),
//! triangulated surface files ([`tin`]), voxel grids of integer codes from VTK ImageData and
//! NumPy files ([`vti`], [`npy`], [`voxels`]) and delimited text tables ([`csv`]). Every reader
//! refuses a bad file with a message naming the file and, where it has one, the line.

pub mod crs;
pub mod csv;
pub mod geojson;
pub mod geokeys;
pub mod geotiff;
pub mod image;
pub mod npy;
pub mod tin;
pub mod voxels;
pub mod vti;

/// The largest absolute coordinate, metres, a file (and a scene) may give: a bound that keeps
/// every distance and area finite and meaningful in f64 (docs/limits.md).
pub const MAX_COORDINATE: f64 = 1e8;
