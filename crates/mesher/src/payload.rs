//! The mesh artifact: the carved terrain, the cave alone and the water, each a closed surface.

use glam::DVec3;
use serde::{Deserialize, Serialize};

use karst_artifact::check::{self, MAX_COORDINATE, ensure};
use karst_artifact::{Invalid, Payload, StageId};

/// The artifact `mesh.bin`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Mesh {
    /// Lattice cell size of the carved terrain, metres.
    pub cell_size: f64,
    /// Lattice cell size of the cave alone and the water, metres.
    pub cave_cell_size: f64,
    /// The carved rock: normals point from rock to air.
    pub terrain: TriMesh,
    /// The karst volume alone: normals point out of the cave, into the rock.
    pub cave: TriMesh,
    /// The water standing or flowing in the conduits: normals point out of the water.
    pub water: TriMesh,
}

impl Mesh {
    /// The surfaces with their names: terrain, cave, water.
    pub fn surfaces(&self) -> [(&'static str, &TriMesh); 3] {
        [("terrain", &self.terrain), ("cave", &self.cave), ("water", &self.water)]
    }
}

impl Payload for Mesh {
    const STAGE: StageId = StageId::Mesher;
    const SCHEMA: u32 = 3;

    /// Cell sizes finite and > 0; finite vertices; triangles of three distinct existing
    /// vertices; a terrain and a cave that are not empty (the water may be).
    fn validate(&self) -> Result<(), Invalid> {
        check::positive(|| "cell_size".into(), self.cell_size, MAX_COORDINATE)?;
        check::positive(|| "cave_cell_size".into(), self.cave_cell_size, MAX_COORDINATE)?;
        for (name, surface) in self.surfaces() {
            if name != "water" {
                ensure(!surface.triangles.is_empty(), || format!("{name}.triangles"), || "is empty".into())?;
            }
            surface.validate(name)?;
        }
        Ok(())
    }
}

/// An indexed triangle mesh; triangles are counter-clockwise seen from outside the solid.
#[derive(Debug, Clone, PartialEq, Default, Serialize, Deserialize)]
pub struct TriMesh {
    pub vertices: Vec<[f32; 3]>,
    pub triangles: Vec<[u32; 3]>,
    /// Field evaluations spent (octree and bricks).
    pub field_evaluations: u64,
    /// What the cleanup took away.
    pub removed: Removed,
}

impl TriMesh {
    fn validate(&self, name: &str) -> Result<(), Invalid> {
        for (i, v) in self.vertices.iter().enumerate() {
            check::position_f32(|| format!("{name}.vertices[{i}]"), v)?;
        }
        let n = self.vertices.len() as u64;
        for (t, tri) in self.triangles.iter().enumerate() {
            if let Some(&v) = tri.iter().find(|&&v| v as u64 >= n) {
                check::index(|| format!("{name}.triangles[{t}]"), v as u64, self.vertices.len())?;
            }
            ensure(
                tri[0] != tri[1] && tri[1] != tri[2] && tri[0] != tri[2],
                || format!("{name}.triangles[{t}]"),
                || format!("{tri:?} repeats a vertex"),
            )?;
        }
        let r = &self.removed;
        check::within(|| format!("{name}.removed.island_volume"), r.island_volume, 0.0, f64::MAX)?;
        check::within(|| format!("{name}.removed.pocket_volume"), r.pocket_volume, 0.0, f64::MAX)
    }

    /// Total area, m².
    pub fn area(&self) -> f64 {
        self.triangles.iter().map(|t| self.normal(t).length() * 0.5).sum()
    }

    /// Volume enclosed by the (closed, outward-oriented) mesh, m³.
    pub fn enclosed_volume(&self) -> f64 {
        self.volume_of(self.triangles.iter())
    }

    /// Signed volume under a set of triangles: Σ a·(b × c)/6.
    pub fn volume_of<'a>(&self, triangles: impl Iterator<Item = &'a [u32; 3]>) -> f64 {
        triangles.map(|t| signed_volume(t.map(|v| self.position(v)))).sum()
    }

    /// Vertex i in double precision.
    pub fn position(&self, i: u32) -> DVec3 {
        glam::Vec3::from_array(self.vertices[i as usize]).as_dvec3()
    }

    /// The triangle's normal, of length twice its area.
    pub fn normal(&self, t: &[u32; 3]) -> DVec3 {
        let [a, b, c] = t.map(|i| self.position(i));
        (b - a).cross(c - a)
    }

    /// Field evaluations per output vertex.
    pub fn evaluations_per_vertex(&self) -> f64 {
        self.field_evaluations as f64 / self.vertices.len().max(1) as f64
    }
}

/// The signed volume under one triangle, a·(b × c)/6, written a·((b − a) × (c − a))/6.
pub fn signed_volume([a, b, c]: [DVec3; 3]) -> f64 {
    a.dot((b - a).cross(c - a)) / 6.0
}

/// The figures of one surface that the stage's headline shows, from a [`TriMesh`] or from a
/// surface written streamed.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SurfaceCounts {
    pub triangles: u64,
    pub vertices: u64,
    pub field_evaluations: u64,
    pub removed: Removed,
}

impl From<&TriMesh> for SurfaceCounts {
    fn from(s: &TriMesh) -> Self {
        SurfaceCounts {
            triangles: s.triangles.len() as u64,
            vertices: s.vertices.len() as u64,
            field_evaluations: s.field_evaluations,
            removed: s.removed,
        }
    }
}

/// What the cleanup took away from one surface.
#[derive(Debug, Clone, Copy, PartialEq, Default, Serialize, Deserialize)]
pub struct Removed {
    /// Rock islands floating in cave air, and their total volume, m³.
    pub islands: u32,
    pub island_volume: f64,
    /// Air pockets sealed in rock, and their total volume, m³.
    pub pockets: u32,
    pub pocket_volume: f64,
}
