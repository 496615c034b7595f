//! Splitting a surface into chunks: square tiles of the horizontal plane, each holding the
//! triangles whose centroid lies in it, with its own copy of their vertices. The page loads and
//! refines chunks independently, so only what is in view gets detail.
//!
//! Tiles are sized so that a chunk holds about [`TARGET_TRIANGLES`] triangles of an evenly
//! spread surface (the cave's are uneven: empty tiles are dropped, dense ones stay whole).
//! Triangles keep their order within a chunk, and chunks come in tile order (x fastest), so the
//! split is deterministic.

use karst_mesher::TriMesh;

/// Triangles per chunk for an evenly spread surface.
pub const TARGET_TRIANGLES: usize = 40_000;

/// Vertex data of one chunk: position and unit normal.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
#[repr(C)]
pub struct Vertex {
    pub position: [f32; 3],
    pub normal: [f32; 3],
}

/// A piece of a surface.
#[derive(Debug, Clone, PartialEq)]
pub struct Chunk {
    pub vertices: Vec<Vertex>,
    /// Three per triangle, into `vertices`.
    pub indices: Vec<u32>,
}

impl Chunk {
    /// The box around the chunk's vertices.
    pub fn bounds(&self) -> ([f32; 3], [f32; 3]) {
        let mut min = [f32::INFINITY; 3];
        let mut max = [f32::NEG_INFINITY; 3];
        for v in &self.vertices {
            for a in 0..3 {
                min[a] = min[a].min(v.position[a]);
                max[a] = max[a].max(v.position[a]);
            }
        }
        (min, max)
    }
}

/// The chunks of `surface` (with one normal per vertex), at most `target` triangles each when
/// the surface is evenly spread.
pub fn split(surface: &TriMesh, normals: &[[f32; 3]], target: usize) -> Vec<Chunk> {
    if surface.triangles.is_empty() {
        return Vec::new();
    }
    let tiles = Tiles::new(surface, target);
    let mut by_tile: Vec<Vec<u32>> = vec![Vec::new(); tiles.count()];
    for (t, triangle) in surface.triangles.iter().enumerate() {
        by_tile[tiles.of(&triangle.map(|v| surface.vertices[v as usize]))].push(t as u32);
    }
    // A vertex's index in the chunk being built, valid when its stamp is that chunk's tile.
    let mut stamp = vec![usize::MAX; surface.vertices.len()];
    let mut local = vec![0u32; surface.vertices.len()];
    by_tile
        .iter()
        .enumerate()
        .filter(|(_, triangles)| !triangles.is_empty())
        .map(|(tile, triangles)| {
            let mut chunk = Chunk { vertices: Vec::new(), indices: Vec::with_capacity(triangles.len() * 3) };
            for &t in triangles {
                for v in surface.triangles[t as usize] {
                    let v = v as usize;
                    if stamp[v] != tile {
                        stamp[v] = tile;
                        local[v] = chunk.vertices.len() as u32;
                        chunk.vertices.push(Vertex { position: surface.vertices[v], normal: normals[v] });
                    }
                    chunk.indices.push(local[v]);
                }
            }
            chunk
        })
        .collect()
}

/// The square tiles over the surface's horizontal extent.
struct Tiles {
    origin: [f32; 2],
    edge: f32,
    nx: usize,
    ny: usize,
}

impl Tiles {
    fn new(surface: &TriMesh, target: usize) -> Tiles {
        let (mut min, mut max) = ([f32::INFINITY; 2], [f32::NEG_INFINITY; 2]);
        for v in &surface.vertices {
            for a in 0..2 {
                min[a] = min[a].min(v[a]);
                max[a] = max[a].max(v[a]);
            }
        }
        let size = [max[0] - min[0], max[1] - min[1]].map(|s| s.max(1e-3));
        let count = surface.triangles.len().div_ceil(target.max(1)).max(1);
        let edge = (size[0] * size[1] / count as f32).sqrt();
        let [nx, ny] = size.map(|s| ((s / edge).ceil() as usize).max(1));
        Tiles { origin: min, edge, nx, ny }
    }

    fn count(&self) -> usize {
        self.nx * self.ny
    }

    /// The tile of a triangle's centroid.
    fn of(&self, corners: &[[f32; 3]; 3]) -> usize {
        let index = |a: usize, n: usize| {
            let centroid = (corners[0][a] + corners[1][a] + corners[2][a]) / 3.0;
            (((centroid - self.origin[a]) / self.edge).floor().max(0.0) as usize).min(n - 1)
        };
        index(1, self.ny) * self.nx + index(0, self.nx)
    }
}

#[cfg(test)]
pub(crate) mod tests {
    use super::*;

    /// A flat grid of n × n quads over [0, n]², two triangles each.
    pub(crate) fn grid(n: u32) -> TriMesh {
        let vertices = (0..=n).flat_map(|j| (0..=n).map(move |i| [i as f32, j as f32, 0.0])).collect();
        let at = |i: u32, j: u32| j * (n + 1) + i;
        let triangles = (0..n)
            .flat_map(|j| (0..n).map(move |i| (i, j)))
            .flat_map(|(i, j)| {
                [[at(i, j), at(i + 1, j), at(i + 1, j + 1)], [at(i, j), at(i + 1, j + 1), at(i, j + 1)]]
            })
            .collect();
        TriMesh { vertices, triangles, ..TriMesh::default() }
    }

    #[test]
    fn every_triangle_lands_in_exactly_one_chunk_with_its_positions() {
        let surface = grid(40);
        let normals = vec![[0.0, 0.0, 1.0]; surface.vertices.len()];
        let chunks = split(&surface, &normals, 500);
        assert!(chunks.len() >= 4, "{} chunks", chunks.len());
        let mut seen: Vec<[[i32; 3]; 3]> = chunks
            .iter()
            .flat_map(|c| {
                c.indices
                    .chunks(3)
                    .map(|t| [0, 1, 2].map(|k| c.vertices[t[k] as usize].position.map(|x| x.round() as i32)))
            })
            .collect();
        let mut expected: Vec<[[i32; 3]; 3]> = surface
            .triangles
            .iter()
            .map(|t| t.map(|v| surface.vertices[v as usize].map(|x| x.round() as i32)))
            .collect();
        seen.sort();
        expected.sort();
        assert_eq!(seen, expected);
        for c in &chunks {
            assert!(c.indices.len() / 3 <= 2 * 500, "an even grid makes chunks near the target");
        }
    }

    #[test]
    fn an_empty_surface_has_no_chunk() {
        assert!(split(&TriMesh::default(), &[], 100).is_empty());
    }
}
