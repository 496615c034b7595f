//! The mesh artifact and its OBJ export.

use std::path::Path;

use serde::{Deserialize, Serialize};

use karst_artifact::{Kind, Payload, atomic};

/// An indexed triangle mesh; triangles are counter-clockwise seen from the air side.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Mesh {
    pub vertices: Vec<[f32; 3]>,
    pub triangles: Vec<[u32; 3]>,
    /// Lattice cell size used, metres.
    pub cell_size: f64,
    /// Field evaluations spent (octree and bricks).
    pub field_evaluations: u64,
}

impl Payload for Mesh {
    const KIND: Kind = Kind::Mesh;
    const SCHEMA: u32 = 1;
}

impl Mesh {
    /// Total area, m².
    pub fn area(&self) -> f64 {
        self.triangles.iter().map(|t| self.corners(t).1.length() * 0.5).sum()
    }

    /// Volume enclosed by the (closed, outward-oriented) mesh, m³: Σ a·(b × c)/6.
    pub fn enclosed_volume(&self) -> f64 {
        self.triangles
            .iter()
            .map(|t| {
                let ([a, _, _], n) = self.corners(t);
                a.dot(n) / 6.0
            })
            .sum()
    }

    /// Corners of a triangle and its (unnormalized, doubled-area) normal.
    fn corners(&self, t: &[u32; 3]) -> ([glam::DVec3; 3], glam::DVec3) {
        let [a, b, c] = t.map(|i| glam::Vec3::from_array(self.vertices[i as usize]).as_dvec3());
        ([a, b, c], (b - a).cross(c - a))
    }

    /// Writes the mesh as Wavefront OBJ (1-based faces), atomically.
    pub fn write_obj(&self, path: &Path) -> std::io::Result<()> {
        atomic::write_with(path, |w| {
            writeln!(
                w,
                "# karstgen mesh: {} vertices, {} triangles",
                self.vertices.len(),
                self.triangles.len()
            )?;
            for [x, y, z] in &self.vertices {
                writeln!(w, "v {x} {y} {z}")?;
            }
            for [a, b, c] in &self.triangles {
                writeln!(w, "f {} {} {}", a + 1, b + 1, c + 1)?;
            }
            Ok(())
        })
    }
}
