//! Polygonizing the active bricks and welding their vertices into one mesh.

use std::collections::HashMap;

use glam::DVec3;
use rayon::prelude::*;

use crate::lattice::Lattice;
use crate::mesh::Surface;
use crate::octree::{self, BRICK};
use crate::tetra::{self, TETRAHEDRA};
use crate::volume::Volume;

/// A mesh vertex is identified by the lattice edge it lies on: (lower id, higher id).
type EdgeKey = (u64, u64);

/// Where on a rock–air edge the vertex goes is clamped away from the lattice points, so that
/// vertices of different edges never coincide and no triangle degenerates.
const T_MARGIN: f64 = 1e-3;

/// The triangles of one brick, vertices named by edge.
struct BrickPart {
    keys: Vec<EdgeKey>,
    positions: Vec<DVec3>,
    triangles: Vec<[u32; 3]>,
    evaluations: u64,
}

/// Polygonizes the boundary f = 0 of `field` at `cell_size` over its extent.
pub fn polygonize<V: Volume>(field: &V, cell_size: f64) -> Surface {
    let (lo, hi) = field.extent();
    let lattice = Lattice::around(lo, hi, cell_size);
    let (bricks, octree_evaluations) = octree::active_bricks(field, &lattice);
    let bar = karst_artifact::progress::bar(bricks.len() as u64, "mesher");
    let parts: Vec<BrickPart> = bricks
        .par_iter()
        .map(|&at| {
            let part = brick(field, &lattice, at);
            bar.inc(1);
            part
        })
        .collect();
    bar.finish_and_clear();
    weld(parts, octree_evaluations)
}

fn brick<V: Volume>(field: &V, lattice: &Lattice, at: [u64; 3]) -> BrickPart {
    let n = (BRICK + 1) as usize;
    let size = [0, 1, 2].map(|a| (BRICK + 1).min(lattice.dims[a] - at[a]) as usize);
    let mut values = vec![1.0f64; n * n * n];
    let local = |i: usize, j: usize, k: usize| (k * n + j) * n + i;
    // A tetrahedron's edge is at most a cube diagonal, √3 cells, so both values of a rock–air
    // edge lie within √3 cells of zero (1-Lipschitz): beyond 2 cells only the sign matters,
    // and the vertices are those of exact values.
    let reach = lattice.cell * 2.0;
    let mut evaluations = 0;
    for k in 0..size[2] {
        for j in 0..size[1] {
            for i in 0..size[0] {
                let p = [at[0] + i as u64, at[1] + j as u64, at[2] + k as u64];
                values[local(i, j, k)] = field.eval_within(lattice.point(p), reach);
                evaluations += 1;
            }
        }
    }
    let mut part = BrickPart { keys: Vec::new(), positions: Vec::new(), triangles: Vec::new(), evaluations };
    let mut index: HashMap<EdgeKey, u32> = HashMap::new();
    let mut crossings = Vec::new();
    for k in 0..size[2].saturating_sub(1) {
        for j in 0..size[1].saturating_sub(1) {
            for i in 0..size[0].saturating_sub(1) {
                let corner = |c: usize| (i + (c & 1), j + (c >> 1 & 1), k + (c >> 2 & 1));
                let v: [f64; 8] = std::array::from_fn(|c| {
                    let (x, y, z) = corner(c);
                    values[local(x, y, z)]
                });
                if v.iter().all(|&f| f < 0.0) || v.iter().all(|&f| f >= 0.0) {
                    continue;
                }
                crossings.clear();
                for tet in &TETRAHEDRA {
                    tetra::triangles(tet, &v, &mut crossings);
                }
                let global = |c: usize| {
                    let (x, y, z) = corner(c);
                    [at[0] + x as u64, at[1] + y as u64, at[2] + z as u64]
                };
                for tri in &crossings {
                    let ids = tri.map(|(rock, air)| {
                        let (pr, pa) = (global(rock), global(air));
                        let key = ordered(lattice.id(pr), lattice.id(pa));
                        *index.entry(key).or_insert_with(|| {
                            let t = (v[rock] / (v[rock] - v[air])).clamp(T_MARGIN, 1.0 - T_MARGIN);
                            let (a, b) = (lattice.point(pr), lattice.point(pa));
                            part.keys.push(key);
                            part.positions.push(a + (b - a) * t);
                            (part.keys.len() - 1) as u32
                        })
                    });
                    part.triangles.push(ids);
                }
            }
        }
    }
    part
}

fn ordered(a: u64, b: u64) -> EdgeKey {
    (a.min(b), a.max(b))
}

/// Merges brick parts in brick order; a vertex on an edge shared by two bricks keeps the
/// position computed by the first.
fn weld(parts: Vec<BrickPart>, octree_evaluations: u64) -> Surface {
    let mut global: HashMap<EdgeKey, u32> = HashMap::new();
    let mut vertices = Vec::new();
    let mut triangles = Vec::new();
    let mut field_evaluations = octree_evaluations;
    for part in parts {
        field_evaluations += part.evaluations;
        let remap: Vec<u32> = part
            .keys
            .iter()
            .zip(&part.positions)
            .map(|(key, p)| {
                *global.entry(*key).or_insert_with(|| {
                    vertices.push(p.as_vec3().to_array());
                    (vertices.len() - 1) as u32
                })
            })
            .collect();
        triangles.extend(part.triangles.iter().map(|t| t.map(|i| remap[i as usize])));
    }
    Surface { vertices, triangles, field_evaluations, removed: Default::default() }
}
