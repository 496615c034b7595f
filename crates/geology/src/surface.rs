//! Geological surfaces: water tables, inception horizons and faults.
//!
//! A surface is either a plane or a triangulated surface (TIN, [`crate::tin`]).
//!
//! A plane is given by its elevation at a reference point, its dip (degrees below horizontal)
//! and its dip direction (azimuth of steepest descent, degrees clockwise from north = +y). A
//! water table with a hydraulic gradient of 4 % towards its spring is a plane dipping
//! atan(0.04) ≈ 2.29° towards the spring. Water tables and horizons are graphs z = s(x, y)
//! (dip below 90°); faults may be vertical.
//!
//! A TIN is read from a file (GOCAD TSurf `.ts`, or plain `v`/`f` text) when the scene is
//! loaded. Its distance is exact (closest triangle); its sign is that of the closest triangle's
//! upward normal; its elevation is barycentric ([`crate::tin::Tin::elevation_at`]); its
//! [`Surface::normal`] is the area-weighted mean normal, only meaningful for nearly planar
//! surfaces.

use std::sync::Arc;

use serde::{Deserialize, Serialize};

use crate::Point;
use crate::tin::Tin;

/// A named surface (`[[geology.water_tables]]`, `[[geology.horizons]]`, `[[geology.faults]]`).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(try_from = "SurfaceEntry", into = "SurfaceEntry")]
pub struct Surface {
    /// Unique name among surfaces of its kind; springs name their water table.
    pub name: String,
    pub geometry: Geometry,
}

/// The shape of a surface.
#[derive(Debug, Clone, PartialEq)]
pub enum Geometry {
    Plane {
        /// Elevation at `origin`, metres.
        elevation: f64,
        /// Reference point `[x, y]`.
        origin: [f64; 2],
        /// Degrees from 0 (horizontal) to 90 (vertical, faults only).
        dip: f64,
        /// Degrees clockwise from north.
        dip_direction: f64,
        /// The trigonometry of `dip` and `dip_direction`, computed once.
        frame: PlaneFrame,
    },
    Tin {
        /// The file as written in the scene (relative to the scene's folder).
        file: String,
        /// BLAKE3 of the file's bytes, filled when loaded.
        content: String,
        /// The triangles, filled when loaded.
        mesh: Arc<Tin>,
    },
}

/// A plane's orientation as the distances and elevations use it. Every sample's distance to
/// every water table reads it (millions per run), and the sines and cosines of the angles cost
/// more than the distance itself; computed from the angles alone, so moving a plane (its
/// elevation and origin) keeps it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PlaneFrame {
    /// Upward unit normal, pointing to the dip direction.
    normal: Point,
    /// Sine and cosine of the dip direction.
    direction: (f64, f64),
    /// Tangent of the dip.
    slope: f64,
}

impl PlaneFrame {
    /// The frame of a plane dipping `dip` degrees towards `dip_direction` degrees.
    pub fn new(dip: f64, dip_direction: f64) -> Self {
        let (sin_dip, cos_dip) = dip.to_radians().sin_cos();
        let (sin_dir, cos_dir) = dip_direction.to_radians().sin_cos();
        PlaneFrame {
            normal: Point::new(sin_dip * sin_dir, sin_dip * cos_dir, cos_dip),
            direction: (sin_dir, cos_dir),
            slope: dip.to_radians().tan(),
        }
    }
}

/// A surface as written in the scene: a plane's fields, or a `file`.
#[derive(Debug, Clone, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
struct SurfaceEntry {
    name: String,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    elevation: Option<f64>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    origin: Option<[f64; 2]>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    dip: Option<f64>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    dip_direction: Option<f64>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    file: Option<String>,
    #[serde(default, skip_deserializing, skip_serializing_if = "Option::is_none")]
    content: Option<String>,
}

/// A `[[geology.surfaces]]` entry that is neither a plane nor a TIN file; names the surface.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum SurfaceError {
    #[error("surface \"{0}\" is read from a file: origin, dip and dip_direction belong to planes")]
    PlaneFieldsOnFile(String),
    #[error("surface \"{0}\" has both an elevation (plane) and a file (TIN)")]
    PlaneAndFile(String),
    #[error("surface \"{0}\" needs an elevation (plane) or a file (TIN)")]
    NoGeometry(String),
}

impl TryFrom<SurfaceEntry> for Surface {
    type Error = SurfaceError;

    fn try_from(e: SurfaceEntry) -> Result<Self, SurfaceError> {
        let geometry = match (e.elevation, e.file) {
            (Some(elevation), None) => {
                let (dip, dip_direction) = (e.dip.unwrap_or_default(), e.dip_direction.unwrap_or_default());
                Geometry::Plane {
                    elevation,
                    origin: e.origin.unwrap_or_default(),
                    dip,
                    dip_direction,
                    frame: PlaneFrame::new(dip, dip_direction),
                }
            }
            (None, Some(file)) => {
                if e.origin.is_some() || e.dip.is_some() || e.dip_direction.is_some() {
                    return Err(SurfaceError::PlaneFieldsOnFile(e.name));
                }
                Geometry::Tin { file, content: String::new(), mesh: Arc::default() }
            }
            (Some(_), Some(_)) => {
                return Err(SurfaceError::PlaneAndFile(e.name));
            }
            (None, None) => {
                return Err(SurfaceError::NoGeometry(e.name));
            }
        };
        Ok(Surface { name: e.name, geometry })
    }
}

impl From<Surface> for SurfaceEntry {
    fn from(s: Surface) -> Self {
        let mut e = SurfaceEntry {
            name: s.name,
            elevation: None,
            origin: None,
            dip: None,
            dip_direction: None,
            file: None,
            content: None,
        };
        match s.geometry {
            Geometry::Plane { elevation, origin, dip, dip_direction, .. } => {
                (e.elevation, e.origin, e.dip, e.dip_direction) =
                    (Some(elevation), Some(origin), Some(dip), Some(dip_direction));
            }
            Geometry::Tin { file, content, .. } => (e.file, e.content) = (Some(file), Some(content)),
        }
        e
    }
}

impl Surface {
    /// A plane surface.
    pub fn plane(name: &str, elevation: f64, origin: [f64; 2], dip: f64, dip_direction: f64) -> Surface {
        let frame = PlaneFrame::new(dip, dip_direction);
        Surface {
            name: name.into(),
            geometry: Geometry::Plane { elevation, origin, dip, dip_direction, frame },
        }
    }

    /// A triangulated surface.
    pub fn tin(name: &str, file: &str, mesh: Tin) -> Surface {
        Surface {
            name: name.into(),
            geometry: Geometry::Tin { file: file.into(), content: String::new(), mesh: Arc::new(mesh) },
        }
    }

    /// The triangles of a TIN surface.
    pub fn mesh(&self) -> Option<&Tin> {
        match &self.geometry {
            Geometry::Tin { mesh, .. } => Some(mesh),
            Geometry::Plane { .. } => None,
        }
    }

    /// Upward unit normal: exact for a plane (horizontal for a vertical plane, pointing to the
    /// dip direction), the area-weighted mean normal of a TIN.
    pub fn normal(&self) -> Point {
        match &self.geometry {
            Geometry::Plane { frame, .. } => frame.normal,
            Geometry::Tin { mesh, .. } => mesh.mean_normal(),
        }
    }

    /// Signed distance from the surface, positive on the side of the upward normal; 0 within
    /// [`ON_SURFACE`] of it.
    pub fn signed_distance(&self, p: Point) -> f64 {
        on_surface(match &self.geometry {
            Geometry::Plane { elevation, origin, frame, .. } => {
                frame.normal.dot(p - Point::new(origin[0], origin[1], *elevation))
            }
            Geometry::Tin { mesh, .. } => {
                let (q, n) = mesh.closest(p);
                let d = q.distance(p);
                if (p - q).dot(n) < 0.0 { -d } else { d }
            }
        })
    }

    /// Euclidean distance from `p` to the surface.
    pub fn distance(&self, p: Point) -> f64 {
        match &self.geometry {
            Geometry::Plane { .. } => self.signed_distance(p).abs(),
            Geometry::Tin { mesh, .. } => mesh.closest(p).0.distance(p),
        }
    }

    /// min(distance(p), limit), faster than [`Surface::distance`] far from a TIN.
    pub fn distance_within(&self, p: Point, limit: f64) -> f64 {
        match &self.geometry {
            Geometry::Plane { .. } => self.distance(p).min(limit),
            Geometry::Tin { mesh, .. } => mesh.closest_within(p, limit).map_or(limit, |(q, _)| q.distance(p)),
        }
    }

    /// The point of the surface closest to `p`.
    pub fn closest_point(&self, p: Point) -> Point {
        match &self.geometry {
            Geometry::Plane { .. } => p - self.normal() * self.signed_distance(p),
            Geometry::Tin { mesh, .. } => mesh.closest(p).0,
        }
    }

    /// Elevation of the surface at (x, y) (not for vertical surfaces).
    pub fn elevation_at(&self, x: f64, y: f64) -> f64 {
        match &self.geometry {
            Geometry::Plane { elevation, origin, frame, .. } => {
                let (sin, cos) = frame.direction;
                let along = (x - origin[0]) * sin + (y - origin[1]) * cos;
                elevation - frame.slope * along
            }
            Geometry::Tin { mesh, .. } => mesh.elevation_at(x, y),
        }
    }

    /// Signed vertical offset of `p` from the surface: positive above it, 0 within
    /// [`ON_SURFACE`] of it (not for vertical surfaces).
    pub fn height_above(&self, p: Point) -> f64 {
        on_surface(p.z - self.elevation_at(p.x, p.y))
    }
}

/// Distance below which a point lies on a surface: a micrometre, far above the rounding of
/// coordinates of any magnitude on Earth (about 1e-9 m at 1e7 m) and far below any geological
/// distance. Samples placed on a water table carry rounding errors of either sign, larger where
/// coordinates are large; without this tolerance that rounding, not the geometry, would put them
/// in the vadose or the phreatic zone, and moving a scene to projected coordinates would change
/// its network.
pub const ON_SURFACE: f64 = 1e-6;

fn on_surface(d: f64) -> f64 {
    if d.abs() <= ON_SURFACE { 0.0 } else { d }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn plane(dip: f64, dip_direction: f64) -> Surface {
        Surface::plane("s", 100.0, [0.0, 0.0], dip, dip_direction)
    }

    #[test]
    fn plane_dips_towards_its_dip_direction() {
        let east = plane(45.0, 90.0);
        assert!((east.elevation_at(10.0, 0.0) - 90.0).abs() < 1e-9);
        assert!((east.elevation_at(0.0, 10.0) - 100.0).abs() < 1e-9);
        let d = east.distance(Point::new(0.0, 0.0, 110.0));
        assert!((d - 10.0 * std::f64::consts::FRAC_1_SQRT_2).abs() < 1e-9);
        assert!(east.signed_distance(Point::new(0.0, 0.0, 110.0)) > 0.0);
        assert!((east.height_above(Point::new(10.0, 0.0, 95.0)) - 5.0).abs() < 1e-9);
        assert!(east.distance(east.closest_point(Point::new(3.0, 4.0, 120.0))) < 1e-9);
    }

    #[test]
    fn vertical_fault_distance_is_horizontal() {
        let fault = plane(90.0, 0.0);
        assert!((fault.distance(Point::new(3.0, -7.0, 55.0)) - 7.0).abs() < 1e-9);
    }

    #[test]
    fn tin_answers_like_the_plane_it_triangulates() {
        let p = plane(10.0, 90.0);
        let corners = [[-100.0, -100.0], [100.0, -100.0], [100.0, 100.0], [-100.0, 100.0]];
        let vertices = corners.iter().map(|c| [c[0], c[1], p.elevation_at(c[0], c[1])]).collect();
        let tin = Surface::tin("t", "t.ts", Tin::new(vertices, vec![[0, 1, 2], [0, 2, 3]], "t.ts").unwrap());
        for q in [Point::new(10.0, 20.0, 130.0), Point::new(-50.0, 0.0, 60.0)] {
            assert!((tin.signed_distance(q) - p.signed_distance(q)).abs() < 1e-9);
            assert!((tin.height_above(q) - p.height_above(q)).abs() < 1e-9);
        }
        assert!((tin.normal() - p.normal()).length() < 1e-12);
    }
}
