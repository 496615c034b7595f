//! Coordinate reference systems: the scene's `crs = "EPSG:NNNN"` and the CRS each data file
//! carries (a GeoTIFF's GeoKeys, a GeoJSON's `crs` member).
//!
//! karstgen does not reproject: every file must be in the scene's CRS, and a file in another
//! one is refused with a message naming both. The CRS is identified by its EPSG code only;
//! karstgen works in metres with z up, so the CRS must be projected (GeoTIFFs in degrees are
//! refused where they are read, [`crate::geotiff`]). A scene that declares no `crs` but reads a
//! file that carries one is refused too, with the line to add: a georeferenced scene says so.

use std::fmt;

/// An EPSG code.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord)]
pub struct Epsg(pub u32);

impl fmt::Display for Epsg {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "EPSG:{}", self.0)
    }
}

/// A CRS name that is not `EPSG:NNNN`.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[error("\"{0}\" is not of the form \"EPSG:NNNN\"")]
pub struct NotEpsg(pub String);

impl Epsg {
    /// Parses `EPSG:NNNN` (any case), as a scene writes it.
    pub fn parse(text: &str) -> Result<Epsg, NotEpsg> {
        let code = text
            .split_once(':')
            .filter(|(authority, _)| authority.trim().eq_ignore_ascii_case("epsg"))
            .and_then(|(_, code)| code.trim().parse::<u32>().ok())
            .filter(|code| *code > 0);
        code.map(Epsg).ok_or_else(|| NotEpsg(text.into()))
    }

    /// The code of an OGC URN or a plain name as GeoJSON writes it: `urn:ogc:def:crs:EPSG::2154`,
    /// `EPSG:2154`; None for anything else (`urn:ogc:def:crs:OGC:1.3:CRS84`).
    pub fn from_name(name: &str) -> Option<Epsg> {
        let mut parts = name.rsplit(':').filter(|p| !p.is_empty());
        let code = parts.next()?.trim().parse::<u32>().ok()?;
        let authority = parts.find(|p| !p.chars().all(|c| c.is_ascii_digit() || c == '.'))?;
        authority.eq_ignore_ascii_case("epsg").then_some(Epsg(code))
    }
}

/// The CRS found in one data file, and where the scene names that file.
#[derive(Debug, Clone)]
pub struct FileCrs {
    /// The scene field that names the file (`terrain.file`).
    pub field: String,
    pub file: String,
    pub crs: Epsg,
}

/// Every file's CRS against the scene's: (field, message) for each disagreement.
pub fn disagreements(declared: Option<Epsg>, files: &[FileCrs]) -> Vec<(String, String)> {
    files
        .iter()
        .filter_map(|f| match declared {
            Some(scene) if scene != f.crs => Some((
                f.field.clone(),
                format!(
                    "{} is in {}, the scene in {scene} (crs): karstgen does not reproject; convert the file (gdalwarp -t_srs {scene}) or fix the scene's crs",
                    f.file, f.crs
                ),
            )),
            Some(_) => None,
            None => Some((
                f.field.clone(),
                format!(
                    "{} is in {}, but the scene declares no crs: add `crs = \"{}\"` at the top of the scene",
                    f.file, f.crs, f.crs
                ),
            )),
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn parses_scene_codes_and_geojson_names() {
        assert_eq!(Epsg::parse("EPSG:2154"), Ok(Epsg(2154)));
        assert_eq!(Epsg::parse("epsg: 32631"), Ok(Epsg(32631)));
        assert!(Epsg::parse("2154").unwrap_err().to_string().contains("\"2154\" is not of the form"));
        assert!(Epsg::parse("ESRI:102110").is_err() && Epsg::parse("EPSG:0").is_err());
        assert_eq!(Epsg::from_name("urn:ogc:def:crs:EPSG::2154"), Some(Epsg(2154)));
        assert_eq!(Epsg::from_name("urn:ogc:def:crs:EPSG:9.9.1:2056"), Some(Epsg(2056)));
        assert_eq!(Epsg::from_name("EPSG:4326"), Some(Epsg(4326)));
        assert_eq!(Epsg::from_name("urn:ogc:def:crs:OGC:1.3:CRS84"), None);
    }

    #[test]
    fn every_file_must_match_the_scene() {
        let file = |crs| FileCrs { field: "terrain.file".into(), file: "dem.tif".into(), crs: Epsg(crs) };
        assert!(disagreements(Some(Epsg(2154)), &[file(2154)]).is_empty());
        let wrong = disagreements(Some(Epsg(2154)), &[file(32631)]);
        assert_eq!(wrong[0].0, "terrain.file");
        assert!(wrong[0].1.contains("dem.tif is in EPSG:32631, the scene in EPSG:2154"), "{wrong:?}");
        let undeclared = disagreements(None, &[file(2056)]);
        assert!(undeclared[0].1.contains("add `crs = \"EPSG:2056\"`"), "{undeclared:?}");
    }
}
