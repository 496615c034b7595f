//! Levels of detail of a chunk: the chunk itself, then coarser copies with about a quarter of
//! the triangles of the level before, made by meshoptimizer's edge-collapse simplifier
//! (`meshopt` crate) from the full chunk.
//!
//! Level k may stray at most 2ᵏ lattice cells from the full chunk (the error limit stops the
//! simplifier earlier where a coarser copy would lose the shape, e.g. thin sheets of water), so
//! a chain can end before [`MAX_LEVELS`]. The vertices on the chunk's border are locked, so that neighbouring chunks shown at
//! different levels still meet without a crack. Each level records its geometric error in
//! metres (meshoptimizer's estimate of how far the simplified surface strays from the full
//! one): the page picks, per chunk, the coarsest level whose error projects to less than a
//! pixel or two on screen. The simplified levels are for display only; they need not be
//! closed or manifold like the mesher's own surfaces (docs/mesher.md).
//!
//! Every level is reordered for the GPU's vertex cache and its vertices for fetch order, which
//! is also what makes the meshopt codec of [`crate::glb`] compress well.

use meshopt::{SimplifyOptions, VertexDataAdapter};

use crate::chunks::{Chunk, Vertex};

/// A level stops the chain when it keeps more than this fraction of the level before (the
/// locked border or the shape allows no more).
const MIN_REDUCTION: f64 = 0.6;
/// No level coarser than this many triangles is made.
const MIN_TRIANGLES: usize = 200;
/// At most this many levels, the full chunk included.
pub const MAX_LEVELS: usize = 4;

/// One level of detail.
#[derive(Debug, Clone, PartialEq)]
pub struct Level {
    pub chunk: Chunk,
    /// Largest distance from the full chunk, metres (0 for the full chunk).
    pub error: f32,
}

/// The levels of `chunk`, meshed at lattice cell `cell_size` metres, finest first.
pub fn levels(chunk: &Chunk, cell_size: f32) -> Vec<Level> {
    let mut levels = vec![Level { chunk: optimized(chunk, chunk.indices.clone()), error: 0.0 }];
    let bytes = meshopt::typed_to_bytes(&chunk.vertices);
    let adapter =
        VertexDataAdapter::new(bytes, std::mem::size_of::<Vertex>(), 0).expect("vertices are whole structs");
    let mut triangles = chunk.indices.len() / 3;
    while levels.len() < MAX_LEVELS && triangles / 4 >= MIN_TRIANGLES {
        let target = triangles / 4;
        let mut error = 0.0f32;
        let indices = meshopt::simplify(
            &chunk.indices,
            &adapter,
            target * 3,
            cell_size * (1 << levels.len()) as f32,
            SimplifyOptions::LockBorder | SimplifyOptions::ErrorAbsolute,
            Some(&mut error),
        );
        let kept = indices.len() / 3;
        if kept == 0 || kept as f64 > MIN_REDUCTION * triangles as f64 {
            break;
        }
        levels.push(Level { chunk: optimized(chunk, indices), error });
        triangles = kept;
    }
    levels
}

/// The triangles `indices` of `chunk` with only the vertices they use, in cache and fetch order.
fn optimized(chunk: &Chunk, indices: Vec<u32>) -> Chunk {
    let mut indices = meshopt::optimize_vertex_cache(&indices, chunk.vertices.len());
    let vertices = meshopt::optimize_vertex_fetch(&mut indices, &chunk.vertices);
    Chunk { vertices, indices }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::chunks::{split, tests::grid};

    #[test]
    fn levels_get_coarser_and_keep_the_border() {
        let surface = grid(60);
        let normals = vec![[0.0, 0.0, 1.0]; surface.vertices.len()];
        let chunk = split(&surface, &normals, usize::MAX).remove(0);
        let levels = levels(&chunk, 1.0);
        assert!(levels.len() >= 3, "{} levels", levels.len());
        assert_eq!(levels[0].chunk.indices.len(), chunk.indices.len());
        for pair in levels.windows(2) {
            assert!(pair[1].chunk.indices.len() * 2 < pair[0].chunk.indices.len());
            assert!(pair[1].error >= pair[0].error);
            assert!(pair[1].error <= 2.0f32.powi(levels.len() as i32), "the error stays within its limit");
        }
        // The border of the square, every unit point of it, is in every level.
        let on_border = |p: &[f32; 3]| p[0] == 0.0 || p[0] == 60.0 || p[1] == 0.0 || p[1] == 60.0;
        for level in &levels {
            let border = level.chunk.vertices.iter().filter(|v| on_border(&v.position)).count();
            assert_eq!(border, 240, "the 240 border points of the grid stay");
        }
    }
}
