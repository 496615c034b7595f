//! Polygonizing the active bricks by marching cubes and welding their vertices into one mesh.
//!
//! Three parallel passes over the active bricks (in (z, y, x) order), none of which depends on
//! the number of threads:
//!
//! 1. each brick evaluates the field at the lattice points it owns, [at, at + BRICK)³;
//! 2. each brick assembles the (BRICK + 1)³ corner values of its cells from its own and its
//!    active neighbours' points (evaluating only those of inactive neighbours), runs marching
//!    cubes ([`crate::cubes`]) and names every vertex by its lattice edge: the edge belongs to
//!    the brick that owns its lower point, always an active brick since the surface crosses
//!    its box;
//! 3. vertices are numbered brick by brick (a brick's own vertices in edge order), and every
//!    triangle's edges are resolved to those numbers.
//!
//! No hash map, no seam: a vertex shared by up to four bricks exists once, computed by its
//! owner from the same two field values every brick sees.

use glam::DVec3;
use rayon::prelude::*;

use crate::cubes::{EDGES, table};
use crate::lattice::Lattice;
use crate::mesh::Surface;
use crate::octree::{self, BRICK};
use crate::volume::Volume;

/// Where on a rock–air edge the vertex goes is clamped away from the lattice points, so that
/// vertices of different edges never coincide and no triangle degenerates.
const T_MARGIN: f64 = 1e-3;

const B: usize = BRICK as usize;
/// Points a brick owns.
const OWN: usize = B * B * B;

/// Points per axis of a brick's cells.
const N: usize = B + 1;
/// Vertex slots of a brick: axis · N³ + the local index of the edge's lower point for edge
/// vertices, then two per cell for the centres of marching cubes' loops that need one.
const EDGE_SLOTS: usize = 3 * N * N * N;
const SLOTS: usize = EDGE_SLOTS + 2 * B * B * B;

/// A vertex as a brick sees it: its owner (0: itself, else the neighbour's offset bits
/// x + 2y + 4z, each a step of BRICK) above bit 9, the edge's slot in its owner below.
type VertexRef = u16;
const SLOT_BITS: u32 = 9;

/// What pass 2 leaves of a brick.
struct BrickPart {
    /// The brick's own vertices, by slot (increasing), with their positions.
    slots: Vec<u16>,
    positions: Vec<[f32; 3]>,
    triangles: Vec<[VertexRef; 3]>,
    /// Indices (in the brick list) of the 7 upper neighbours, by offset bits − 1.
    neighbours: [u32; 7],
    evaluations: u64,
}

/// Polygonizes the boundary f = 0 of `field` at `cell_size` over its extent.
pub fn polygonize<V: Volume>(field: &V, cell_size: f64) -> Surface {
    let (lo, hi) = field.extent();
    let lattice = Lattice::around(lo, hi, cell_size);
    let (bricks, octree_evaluations) = octree::active_bricks(field, &lattice);
    // A cell edge is one cell long, so both values of a rock–air edge lie within a cell of zero
    // (1-Lipschitz): beyond that only the sign matters, and vertices are those of exact values.
    let reach = lattice.cell * 1.5;
    let bar = karst_artifact::progress::bar(2 * bricks.len() as u64, "mesher");
    let own: Vec<Vec<f64>> = bricks
        .par_iter()
        .map(|&at| {
            let values = own_values(field, &lattice, at, reach);
            bar.inc(1);
            values
        })
        .collect();
    let parts: Vec<BrickPart> = (0..bricks.len())
        .into_par_iter()
        .map_init(Scratch::default, |scratch, b| {
            let part = brick(field, &lattice, &bricks, &own, b, reach, scratch);
            bar.inc(1);
            part
        })
        .collect();
    bar.finish_and_clear();
    let own_evaluations: u64 = own.iter().map(|v| v.iter().filter(|x| !x.is_nan()).count() as u64).sum();
    drop(own);
    weld(parts, octree_evaluations + own_evaluations)
}

fn local(i: usize, j: usize, k: usize) -> usize {
    (k * B + j) * B + i
}

/// The values at the points brick `at` owns (NaN beyond the lattice).
fn own_values<V: Volume>(field: &V, lattice: &Lattice, at: [u64; 3], reach: f64) -> Vec<f64> {
    let size = [0, 1, 2].map(|a| BRICK.min(lattice.dims[a] - at[a]) as usize);
    let mut points = Vec::with_capacity(OWN);
    for k in 0..size[2] {
        for j in 0..size[1] {
            for i in 0..size[0] {
                points.push(lattice.point([at[0] + i as u64, at[1] + j as u64, at[2] + k as u64]));
            }
        }
    }
    let mut values = Vec::with_capacity(points.len());
    let end = [0, 1, 2].map(|a| at[a] + size[a] as u64 - 1);
    field.eval_block(lattice.point(at), lattice.point(end), reach, &points, &mut values);
    let mut out = vec![f64::NAN; OWN];
    let mut next = values.into_iter();
    for k in 0..size[2] {
        for j in 0..size[1] {
            for i in 0..size[0] {
                out[local(i, j, k)] = next.next().expect("one value per point");
            }
        }
    }
    out
}

/// Buffers a thread reuses from brick to brick (every brick overwrites what it reads).
#[derive(Default)]
struct Scratch {
    values: Vec<f64>,
    made: Vec<bool>,
    missing: Vec<(usize, usize, usize)>,
    positions: Vec<(u16, [f32; 3])>,
}

fn brick<V: Volume>(
    field: &V,
    lattice: &Lattice,
    bricks: &[[u64; 3]],
    own: &[Vec<f64>],
    b: usize,
    reach: f64,
    scratch: &mut Scratch,
) -> BrickPart {
    let at = bricks[b];
    let n = N;
    let size = [0, 1, 2].map(|a| (BRICK + 1).min(lattice.dims[a] - at[a]) as usize);
    let find = |q: [u64; 3]| bricks.binary_search_by_key(&[q[2], q[1], q[0]], |c| [c[2], c[1], c[0]]).ok();
    let neighbours: [Option<usize>; 7] = std::array::from_fn(|o| {
        let bits = o + 1;
        find([0, 1, 2].map(|a| at[a] + BRICK * (bits >> a & 1) as u64))
    });
    let index = |i: usize, j: usize, k: usize| (k * n + j) * n + i;
    let Scratch { values, made, missing, positions: positions_by_slot } = scratch;
    values.clear();
    values.resize(n * n * n, f64::NAN);
    missing.clear();
    for k in 0..size[2] {
        for j in 0..size[1] {
            for i in 0..size[0] {
                let bits = (i / B) | (j / B) << 1 | (k / B) << 2;
                let owner = if bits == 0 { Some(b) } else { neighbours[bits - 1] };
                match owner {
                    Some(o) => values[index(i, j, k)] = own[o][local(i % B, j % B, k % B)],
                    None => missing.push((i, j, k)),
                }
            }
        }
    }
    let mut evaluations = 0;
    if !missing.is_empty() {
        let points: Vec<DVec3> = missing
            .iter()
            .map(|&(i, j, k)| lattice.point([at[0] + i as u64, at[1] + j as u64, at[2] + k as u64]))
            .collect();
        let end = [0, 1, 2].map(|a| at[a] + size[a] as u64 - 1);
        let mut found = Vec::with_capacity(points.len());
        field.eval_block(lattice.point(at), lattice.point(end), reach, &points, &mut found);
        for (&(i, j, k), v) in missing.iter().zip(found) {
            values[index(i, j, k)] = v;
        }
        evaluations = missing.len() as u64;
    }

    // The vertex of a crossed edge belongs to the brick of the canonical cell of that edge:
    // among the (up to four) cells around it, the one with the highest coordinates. That cell
    // is crossed by the surface, so its brick is active and makes the vertex; relative to any
    // other cell of the edge it is this brick or an upper neighbour.
    let last = [0, 1, 2].map(|a| lattice.dims[a] - 1);
    made.clear();
    made.resize(SLOTS, false);
    positions_by_slot.clear();
    let mut triangles = Vec::new();
    let cases = table();
    for k in 0..size[2].saturating_sub(1) {
        for j in 0..size[1].saturating_sub(1) {
            for i in 0..size[0].saturating_sub(1) {
                let corner = |c: usize| [i + (c & 1), j + (c >> 1 & 1), k + (c >> 2 & 1)];
                let v: [f64; 8] = std::array::from_fn(|c| {
                    let [x, y, z] = corner(c);
                    values[index(x, y, z)]
                });
                let case = (0..8).fold(0usize, |m, c| m | ((v[c] < 0.0) as usize) << c);
                if case == 0 || case == 255 {
                    continue;
                }
                let global = |c: usize| {
                    let [x, y, z] = corner(c);
                    lattice.point([at[0] + x as u64, at[1] + y as u64, at[2] + z as u64])
                };
                let edge_position = |e: usize| {
                    let (a, c) = EDGES[e];
                    let (rock, air) = if v[a] < 0.0 { (a, c) } else { (c, a) };
                    let t = (v[rock] / (v[rock] - v[air])).clamp(T_MARGIN, 1.0 - T_MARGIN);
                    let (pr, pa) = (global(rock), global(air));
                    pr + (pa - pr) * t
                };
                let surface = &cases[case];
                for tri in &surface.triangles {
                    triangles.push(tri.map(|e| {
                        let e = e as usize;
                        if e >= 12 {
                            // A loop's centre, private to this cell.
                            let slot = EDGE_SLOTS + 2 * local(i, j, k) + (e - 12);
                            if !made[slot] {
                                made[slot] = true;
                                let ring = &surface.centres[e - 12];
                                let sum: DVec3 = ring.iter().map(|&r| edge_position(r as usize)).sum();
                                let centre = sum / ring.len() as f64;
                                positions_by_slot.push((slot as u16, centre.as_vec3().to_array()));
                            }
                            return slot as u16;
                        }
                        let (a, c) = EDGES[e];
                        let axis = (c - a).trailing_zeros() as usize;
                        let q = corner(a);
                        let cell = |d: usize| {
                            if d != axis && at[d] + q[d] as u64 == last[d] { q[d] - 1 } else { q[d] }
                        };
                        let bits = (cell(0) / B) | (cell(1) / B) << 1 | (cell(2) / B) << 2;
                        let o = [0, 1, 2].map(|d| q[d] - B * (bits >> d & 1));
                        let slot = axis * N * N * N + (o[2] * N + o[1]) * N + o[0];
                        if bits == 0 && !made[slot] {
                            made[slot] = true;
                            positions_by_slot.push((slot as u16, edge_position(e).as_vec3().to_array()));
                        }
                        ((bits as u16) << SLOT_BITS) | slot as u16
                    }));
                }
            }
        }
    }
    positions_by_slot.sort_unstable_by_key(|&(slot, _)| slot);
    BrickPart {
        slots: positions_by_slot.iter().map(|&(s, _)| s).collect(),
        positions: positions_by_slot.iter().map(|&(_, p)| p).collect(),
        triangles,
        neighbours: neighbours.map(|o| o.map_or(u32::MAX, |o| o as u32)),
        evaluations,
    }
}

/// Numbers the vertices brick by brick and resolves every triangle's references.
fn weld(parts: Vec<BrickPart>, evaluations: u64) -> Surface {
    let mut base = Vec::with_capacity(parts.len() + 1);
    base.push(0u32);
    for part in &parts {
        base.push(base.last().unwrap() + part.slots.len() as u32);
    }
    let resolve = |b: usize, r: VertexRef| -> u32 {
        let (bits, slot) = ((r >> SLOT_BITS) as usize, r & ((1 << SLOT_BITS) - 1));
        let owner = if bits == 0 { b } else { parts[b].neighbours[bits - 1] as usize };
        let rank = parts[owner].slots.binary_search(&slot).expect("the owner made the vertex");
        base[owner] + rank as u32
    };
    // Each brick resolves its triangles into its own range of the output.
    let mut triangles = vec![[0u32; 3]; parts.iter().map(|p| p.triangles.len()).sum()];
    let mut ranges = Vec::with_capacity(parts.len());
    let mut rest = triangles.as_mut_slice();
    for part in &parts {
        let (range, tail) = rest.split_at_mut(part.triangles.len());
        ranges.push(range);
        rest = tail;
    }
    ranges.into_par_iter().enumerate().for_each(|(b, range)| {
        for (out, t) in range.iter_mut().zip(&parts[b].triangles) {
            *out = t.map(|r| resolve(b, r));
        }
    });
    let field_evaluations = evaluations + parts.iter().map(|p| p.evaluations).sum::<u64>();
    let mut vertices = Vec::with_capacity(*base.last().unwrap() as usize);
    for part in parts {
        vertices.extend(part.positions);
    }
    Surface { vertices, triangles, field_evaluations, removed: Default::default() }
}
