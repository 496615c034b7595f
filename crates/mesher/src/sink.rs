//! Where the polygonizer hands the mesh over, region by region as the regions are finished:
//! an in-memory [`TriMesh`], or a writer that never holds the whole mesh (a file, a hash).

use crate::payload::TriMesh;

/// Receives a mesh in pieces: vertices numbered in the order they are given (the first given
/// is 0), and triangles that name only vertices already given. Concatenating every piece
/// gives the vertices and the triangles of the whole mesh, whatever the size of the pieces.
pub trait MeshSink {
    type Error;

    /// The next vertices, numbered after those already given.
    fn vertices(&mut self, vertices: &[[f32; 3]]) -> Result<(), Self::Error>;

    /// The next triangles.
    fn triangles(&mut self, triangles: &[[u32; 3]]) -> Result<(), Self::Error>;
}

/// Gathers the whole mesh in memory.
impl MeshSink for TriMesh {
    type Error = std::convert::Infallible;

    fn vertices(&mut self, vertices: &[[f32; 3]]) -> Result<(), Self::Error> {
        self.vertices.extend_from_slice(vertices);
        Ok(())
    }

    fn triangles(&mut self, triangles: &[[u32; 3]]) -> Result<(), Self::Error> {
        self.triangles.extend_from_slice(triangles);
        Ok(())
    }
}
