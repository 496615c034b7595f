//! Geometries as a GeoPackage stores them: the GeoPackage binary header (magic `GP`, version
//! 0, flags, SRS id, envelope) followed by the geometry in ISO Well-Known Binary, little
//! endian (OGC GeoPackage 1.3, clause 2.1.3; ISO 13249-3 WKB, whose Z types add 1000 to the
//! 2D type code).
//!
//! Coordinates are rounded to the millimetre before they are written, so that the file holds
//! what the exports promise and no float noise of the local-to-world translation.

/// ISO WKB type codes.
const POINT_Z: u32 = 1001;
const LINESTRING_Z: u32 = 1002;
const POLYGON: u32 = 3;
const MULTIPOLYGON: u32 = 6;

/// A geometry of the export's layers, in world coordinates.
#[derive(Debug, Clone, PartialEq)]
pub enum Geometry {
    PointZ([f64; 3]),
    LineStringZ(Vec<[f64; 3]>),
    /// Polygons of one outer ring each (closed, counter-clockwise).
    MultiPolygon(Vec<Vec<[f64; 2]>>),
}

/// A coordinate to the millimetre.
pub fn millimetre(v: f64) -> f64 {
    (v * 1000.0).round() / 1000.0
}

impl Geometry {
    /// The geometry type name of `gpkg_geometry_columns`.
    pub fn type_name(&self) -> &'static str {
        match self {
            Geometry::PointZ(_) => "POINT",
            Geometry::LineStringZ(_) => "LINESTRING",
            Geometry::MultiPolygon(_) => "MULTIPOLYGON",
        }
    }

    /// Whether the geometry has z values.
    pub fn has_z(&self) -> bool {
        !matches!(self, Geometry::MultiPolygon(_))
    }

    /// The map box `[min x, max x, min y, max y]` (the R-tree's and the envelope's order).
    pub fn envelope(&self) -> [f64; 4] {
        let mut e = [f64::INFINITY, f64::NEG_INFINITY, f64::INFINITY, f64::NEG_INFINITY];
        let mut add = |x: f64, y: f64| {
            let (x, y) = (millimetre(x), millimetre(y));
            e = [e[0].min(x), e[1].max(x), e[2].min(y), e[3].max(y)];
        };
        match self {
            Geometry::PointZ(p) => add(p[0], p[1]),
            Geometry::LineStringZ(points) => points.iter().for_each(|p| add(p[0], p[1])),
            Geometry::MultiPolygon(rings) => rings.iter().flatten().for_each(|p| add(p[0], p[1])),
        }
        e
    }

    /// The GeoPackage binary blob: header with the SRS id and an xy envelope (none for a
    /// point, whose envelope is itself), then ISO WKB.
    pub fn to_gpkg(&self, srs_id: i32) -> Vec<u8> {
        let mut out = Vec::with_capacity(64);
        out.extend_from_slice(b"GP");
        out.push(0);
        let envelope = !matches!(self, Geometry::PointZ(_));
        // Bit 0: little endian; bits 1-3: envelope [minx, maxx, miny, maxy] (1) or none (0).
        out.push(if envelope { 0b0000_0011 } else { 0b0000_0001 });
        out.extend_from_slice(&srs_id.to_le_bytes());
        if envelope {
            self.envelope().iter().for_each(|v| out.extend_from_slice(&v.to_le_bytes()));
        }
        self.write_wkb(&mut out);
        out
    }

    fn write_wkb(&self, out: &mut Vec<u8>) {
        let coordinate = |out: &mut Vec<u8>, v: f64| out.extend_from_slice(&millimetre(v).to_le_bytes());
        let header = |out: &mut Vec<u8>, code: u32| {
            out.push(1);
            out.extend_from_slice(&code.to_le_bytes());
        };
        let count = |out: &mut Vec<u8>, n: usize| out.extend_from_slice(&(n as u32).to_le_bytes());
        match self {
            Geometry::PointZ(p) => {
                header(out, POINT_Z);
                p.iter().for_each(|&v| coordinate(out, v));
            }
            Geometry::LineStringZ(points) => {
                header(out, LINESTRING_Z);
                count(out, points.len());
                points.iter().flatten().for_each(|&v| coordinate(out, v));
            }
            Geometry::MultiPolygon(rings) => {
                header(out, MULTIPOLYGON);
                count(out, rings.len());
                for ring in rings {
                    header(out, POLYGON);
                    count(out, 1);
                    count(out, ring.len());
                    ring.iter().flatten().for_each(|&v| coordinate(out, v));
                }
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_point_is_header_then_iso_wkb() {
        let blob = Geometry::PointZ([651234.5671, 6862345.678, 362.2]).to_gpkg(2154);
        assert_eq!(&blob[..4], b"GP\x00\x01");
        assert_eq!(i32::from_le_bytes(blob[4..8].try_into().unwrap()), 2154);
        assert_eq!(blob[8], 1, "little endian");
        assert_eq!(u32::from_le_bytes(blob[9..13].try_into().unwrap()), 1001);
        let x = f64::from_le_bytes(blob[13..21].try_into().unwrap());
        assert_eq!(x, 651234.567, "to the millimetre");
        assert_eq!(blob.len(), 8 + 5 + 24);
    }

    #[test]
    fn a_line_carries_its_envelope() {
        let line = Geometry::LineStringZ(vec![[1.0, 5.0, 0.0], [-2.0, 7.0, 1.0]]);
        let blob = line.to_gpkg(-1);
        assert_eq!(blob[3], 0b11);
        let read = |at: usize| f64::from_le_bytes(blob[at..at + 8].try_into().unwrap());
        assert_eq!([read(8), read(16), read(24), read(32)], [-2.0, 1.0, 5.0, 7.0]);
        assert_eq!(u32::from_le_bytes(blob[41..45].try_into().unwrap()), 1002);
        assert_eq!(u32::from_le_bytes(blob[45..49].try_into().unwrap()), 2);
        assert_eq!(blob.len(), 40 + 9 + 2 * 24);
    }
}
