//! The GeoKey directory of a GeoTIFF (OGC GeoTIFF 1.1, §7): which CRS the model coordinates are
//! in, their units, and whether a pixel stands for an area or a point.
//!
//! The directory (tag 34735) is a list of unsigned shorts: a header (version 1, revision,
//! minor revision, number of keys), then one entry of four shorts per key: its id, where its
//! value is (0: the fourth short itself; 34736: GeoDoubleParams; 34737: GeoAsciiParams; 34735:
//! the directory), how many values, and the value or offset. karstgen reads the keys below and
//! ignores the rest (citations, datum and ellipsoid parameters).

/// What karstgen needs from the GeoKeys.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct GeoKeys {
    /// GTModelTypeGeoKey (1024): 1 projected, 2 geographic, 3 geocentric.
    pub model_type: Option<u16>,
    /// GTRasterTypeGeoKey (1025): 1 RasterPixelIsArea, 2 RasterPixelIsPoint.
    pub raster_type: Option<u16>,
    /// GeodeticCRSGeoKey / GeographicTypeGeoKey (2048).
    pub geographic: Option<u16>,
    /// ProjectedCRSGeoKey / ProjectedCSTypeGeoKey (3072).
    pub projected: Option<u16>,
    /// ProjLinearUnitsGeoKey (3076): 9001 is the metre.
    pub linear_units: Option<u16>,
    /// VerticalUnitsGeoKey (4099): 9001 is the metre.
    pub vertical_units: Option<u16>,
}

/// A GeoKeyDirectory that cannot be read.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum GeoKeyError {
    #[error("GeoKeyDirectory has {0} values, fewer than its 4-value header")]
    NoHeader(usize),
    #[error("GeoKeyDirectory version {0}, expected 1")]
    Version(u16),
    #[error("GeoKeyDirectory announces {announced} keys but holds {held}")]
    Truncated { announced: u16, held: usize },
    #[error("GeoKey {key} points at value {index} beyond the GeoKeyDirectory's {values} values")]
    OutOfBounds { key: u16, index: u16, values: usize },
    #[error("GeoKey {key} is stored in tag {tag}, not as a short")]
    NotAShort { key: u16, tag: u16 },
}

/// EPSG's code of the metre (unit of measure).
pub const METRE: u16 = 9001;
/// The GeoKey value meaning "user-defined" (no EPSG code).
pub const USER_DEFINED: u16 = 32767;

const GEO_KEY_DIRECTORY: u16 = 34735;

impl GeoKeys {
    /// Reads the keys from the directory's shorts; a directory that ends early or names a key
    /// stored out of its bounds is an error naming the key.
    pub fn parse(directory: &[u16]) -> Result<GeoKeys, GeoKeyError> {
        let [version, _, _, count] = *directory
            .get(..4)
            .and_then(|h| <&[u16; 4]>::try_from(h).ok())
            .ok_or(GeoKeyError::NoHeader(directory.len()))?;
        if version != 1 {
            return Err(GeoKeyError::Version(version));
        }
        let mut keys = GeoKeys::default();
        for k in 0..count as usize {
            let entry = directory
                .get(4 + 4 * k..8 + 4 * k)
                .ok_or(GeoKeyError::Truncated { announced: count, held: (directory.len() - 4) / 4 })?;
            let (id, location, value) = (entry[0], entry[1], entry[3]);
            let short = match location {
                0 => Some(value),
                GEO_KEY_DIRECTORY => {
                    Some(*directory.get(value as usize).ok_or(GeoKeyError::OutOfBounds {
                        key: id,
                        index: value,
                        values: directory.len(),
                    })?)
                }
                _ => None,
            };
            let slot = match id {
                1024 => &mut keys.model_type,
                1025 => &mut keys.raster_type,
                2048 => &mut keys.geographic,
                3072 => &mut keys.projected,
                3076 => &mut keys.linear_units,
                4099 => &mut keys.vertical_units,
                _ => continue,
            };
            *slot = Some(short.ok_or(GeoKeyError::NotAShort { key: id, tag: location })?);
        }
        Ok(keys)
    }

    /// True for RasterPixelIsPoint: the pixel (0, 0) is the point at raster coordinate (0, 0)
    /// rather than the square [0, 1) × [0, 1) (RasterPixelIsArea, the default).
    pub fn pixel_is_point(&self) -> bool {
        self.raster_type == Some(2)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn reads_a_gdal_written_lambert93_directory() {
        // GDAL's keys for EPSG:2154, RasterPixelIsPoint, with a citation in GeoAsciiParams.
        let directory = [1, 1, 0, 4, 1024, 0, 1, 1, 1025, 0, 1, 2, 1026, 34737, 22, 0, 3072, 0, 1, 2154];
        let keys = GeoKeys::parse(&directory).unwrap();
        assert_eq!(keys.projected, Some(2154));
        assert_eq!(keys.model_type, Some(1));
        assert!(keys.pixel_is_point());
        assert_eq!(keys.geographic, None);
    }

    #[test]
    fn short_directories_are_errors() {
        assert!(GeoKeys::parse(&[1, 1]).unwrap_err().to_string().contains("fewer than its 4-value header"));
        assert!(
            GeoKeys::parse(&[1, 1, 0, 2, 1024, 0, 1, 1])
                .unwrap_err()
                .to_string()
                .contains("announces 2 keys")
        );
        assert!(GeoKeys::parse(&[2, 1, 0, 0]).unwrap_err().to_string().contains("version 2"));
        let doubles = [1, 1, 0, 1, 3072, 34736, 1, 0];
        assert!(
            GeoKeys::parse(&doubles).unwrap_err().to_string().contains("GeoKey 3072 is stored in tag 34736")
        );
    }
}
