//! Checking the promises of a surface: every edge shared by exactly two triangles, used once
//! in each direction (closed, 2-manifold, consistently oriented), and no degenerate triangle.

use thiserror::Error;

use crate::payload::TriMesh;

/// The first broken promise found.
#[derive(Debug, Clone, PartialEq, Error)]
pub enum Defect {
    #[error("edge {0}→{1} is used {2} times in that direction")]
    RepeatedEdge(u32, u32, usize),
    #[error("edge {0}→{1} has no opposite edge (the surface is open or inconsistently oriented)")]
    OpenEdge(u32, u32),
    #[error("triangle {0} has zero area")]
    Degenerate(usize),
    #[error("triangle {0} names a vertex that does not exist")]
    BadIndex(usize),
}

/// Ok when the surface is closed, 2-manifold at edges, oriented and without zero-area triangles.
pub fn check(surface: &TriMesh) -> Result<(), Defect> {
    let n = surface.vertices.len() as u32;
    let mut edges = Vec::with_capacity(surface.triangles.len() * 3);
    for (i, t) in surface.triangles.iter().enumerate() {
        if t.iter().any(|&v| v >= n) {
            return Err(Defect::BadIndex(i));
        }
        if surface.normal(t).length_squared() <= 0.0 {
            return Err(Defect::Degenerate(i));
        }
        edges.extend((0..3).map(|e| (t[e], t[(e + 1) % 3])));
    }
    edges.sort_unstable();
    for run in edges.chunk_by(|a, b| a == b) {
        if run.len() > 1 {
            return Err(Defect::RepeatedEdge(run[0].0, run[0].1, run.len()));
        }
    }
    for &(a, b) in &edges {
        if edges.binary_search(&(b, a)).is_err() {
            return Err(Defect::OpenEdge(a, b));
        }
    }
    Ok(())
}
