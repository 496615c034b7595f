//! Polygonizing the active bricks by marching cubes and welding their vertices into one mesh,
//! handed over slab by slab as the slabs are finished.
//!
//! The active bricks are ordered by slabs along the sweep axis ([`sweep_axis`]), then in
//! (z, y, x) order inside a slab. Every step is a parallel pass over the bricks of one slab,
//! none of which depends on the number of threads:
//!
//! 1. each brick evaluates its seeds and centres (its points of even and of odd coordinates);
//! 2. each brick marks its live cells, those its seeds and centres do not prove uniform;
//! 3. each brick evaluates the other points it owns, [at, at + BRICK)³, that are corners of a
//!    live cell (its own or a lower neighbour's);
//! 4. each brick assembles the corner values of its live cells from its own and its active
//!    upper neighbours' points (evaluating only those of inactive neighbours), runs marching
//!    cubes ([`crate::cubes`]) and names every vertex by its lattice edge: the vertex belongs
//!    to the brick of the edge's canonical cell, always an active brick with that cell live
//!    since the surface crosses it;
//! 5. vertices are numbered brick by brick (a brick's own vertices in edge order), and every
//!    triangle's edges are resolved to those numbers.
//!
//! A brick's neighbours are in its slab or the next one (upper) or the previous one (lower),
//! so the passes run as a pipeline along the sweep: when slab s has its seeds, slab s − 1 gets
//! its live cells and its own values, slab s − 2 its marching cubes (its vertices go to the
//! [`MeshSink`] then), and slab s − 3 its triangles resolved and handed over. Only the
//! slabs of that front are in memory, whatever the domain's extent along the sweep.
//!
//! No hash map, no seam: a vertex shared by up to four bricks exists once, computed by its
//! owner from the same two field values every brick sees.

use std::ops::{Index, Range};

use glam::DVec3;
use rayon::prelude::*;

use crate::cubes::{EDGES, table};
use crate::lattice::Lattice;
use crate::octree::{self, BRICK, THICK, order_key};
use crate::payload::TriMesh;
use crate::sink::MeshSink;
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
/// x + 2y + 4z, each a step of BRICK) above bit 9, the edge's slot in its owner below (once
/// the brick is done, its own vertices' rank among its vertices instead).
type VertexRef = u16;
const SLOT_BITS: u32 = 9;

/// What the marching cubes leave of a brick until its triangles are resolved.
struct BrickPart {
    /// The brick's own vertices, by slot (increasing); their positions, until handed over.
    slots: Vec<u16>,
    positions: Vec<[f32; 3]>,
    triangles: Vec<[VertexRef; 3]>,
    /// Indices (in the brick list) of the 7 upper neighbours, by offset bits − 1.
    neighbours: [u32; 7],
    /// The number of the brick's first vertex in the mesh.
    base: u32,
    evaluations: u64,
}

/// Every cell has one corner of even coordinates (its seed) and the opposite one, of odd
/// coordinates (its centre: the centre of a 2³ block of cells). The field is 1-Lipschitz, so a
/// corner whose value exceeds in magnitude the distance to another corner gives that corner
/// its sign; the other corners are 1, √2 or √3 cells from each. In cells, with a margin:
const EDGE: f64 = 1.0001;
const FACE: f64 = 1.41422;
const DIAGONAL: f64 = 1.7321;
/// Seeds and centres are exact up to this many cells (beyond, any value of the same sign and at
/// least as large), enough to decide [`DIAGONAL`].
const SEED_REACH: f64 = 1.75;
/// Seeds (or centres) of a brick: its points of even (odd) local coordinates, by x + 2y + 4z
/// (NaN beyond the lattice, or a centre that no cell needed).
type Seeds = [f64; 8];

/// The values a brick evaluated among the points it owns: bit `local(i, j, k)` of `mask` set
/// for each, `values` in the order of those bits.
#[derive(Default)]
struct Own {
    mask: u64,
    values: Vec<f64>,
}

impl Own {
    /// The value at local point l, if the brick evaluated it.
    fn get(&self, l: usize) -> Option<f64> {
        (self.mask >> l & 1 == 1).then(|| self.values[(self.mask & ((1u64 << l) - 1)).count_ones() as usize])
    }
}

/// Indices (in the brick list) of a brick's neighbours, by offset bits − 1 (x + 2y + 4z, each
/// bit a step of BRICK up or down); `u32::MAX` when that brick is inactive.
type Neighbours = [u32; 7];

/// Per-brick data of the slabs of the front, indexed by the bricks' indices in the brick list:
/// slabs are added at the back as the sweep reaches them and dropped from the front once no
/// pass needs them. The slabs a window holds are consecutive, so it is one run of bricks.
struct Window<T> {
    /// The index of the first brick held.
    first: usize,
    items: std::collections::VecDeque<T>,
}

impl<T> Window<T> {
    fn new() -> Self {
        Window { first: 0, items: Default::default() }
    }

    /// Adds the data of the slab whose first brick is `first`, the one after those held.
    fn push(&mut self, first: usize, items: Vec<T>) {
        if self.items.is_empty() {
            self.first = first;
        }
        debug_assert_eq!(first, self.first + self.items.len(), "slabs are added in order");
        self.items.extend(items);
    }

    /// Drops the bricks before brick `first`.
    fn keep_from(&mut self, first: usize) {
        let n = first.saturating_sub(self.first).min(self.items.len());
        self.items.drain(..n);
        self.first += n;
    }
}

impl<T: Send + 'static> Window<T> {
    /// [`Window::keep_from`] for data that own heap memory: they are freed on a worker thread,
    /// while the calling thread goes on handing the mesh over.
    fn release_from(&mut self, first: usize) {
        let n = first.saturating_sub(self.first).min(self.items.len());
        let gone: Vec<T> = self.items.drain(..n).collect();
        self.first += n;
        if !gone.is_empty() {
            rayon::spawn(move || drop(gone));
        }
    }
}

impl<T> Index<usize> for Window<T> {
    type Output = T;

    fn index(&self, b: usize) -> &T {
        &self.items[b - self.first]
    }
}

/// Polygonizes the boundary f = 0 of `field` at `cell_size` over its extent.
pub fn polygonize<V: Volume>(field: &V, cell_size: f64) -> TriMesh {
    let mut mesh = TriMesh::default();
    let Ok(evaluations) = polygonize_into(field, cell_size, &mut mesh);
    mesh.field_evaluations = evaluations;
    mesh
}

/// [`polygonize`], handing the mesh to `sink` slab by slab (the whole mesh is never in memory
/// unless the sink keeps it); returns the number of field evaluations.
pub fn polygonize_into<V: Volume, S: MeshSink>(
    field: &V,
    cell_size: f64,
    sink: &mut S,
) -> Result<u64, S::Error> {
    polygonize_with(field, cell_size, true, None, sink)
}

/// The axis along which the bricks are swept: the lattice's longest (the first of equals), so
/// that a slab, the section of the domain across it, is the smallest. Along z, a gently
/// sloping ground would lie whole in a few slabs: the front would grow with the domain's area.
fn sweep_axis(lattice: &Lattice) -> usize {
    let d = lattice.dims;
    (0..3).fold(0, |best, a| if d[a] > d[best] { a } else { best })
}

/// [`polygonize_into`]; with `lazy` false every corner of the active bricks is evaluated, and
/// `sweep` forces the sweep axis (tests compare both).
fn polygonize_with<V: Volume, S: MeshSink>(
    field: &V,
    cell_size: f64,
    lazy: bool,
    sweep: Option<usize>,
    sink: &mut S,
) -> Result<u64, S::Error> {
    let (lo, hi) = field.extent();
    let lattice = Lattice::around(lo, hi, cell_size);
    let sweep = sweep.unwrap_or_else(|| sweep_axis(&lattice));
    // A cell edge is one cell long, so both values of a rock–air edge lie within a cell of zero
    // (1-Lipschitz): beyond that only the sign matters, and vertices are those of exact values.
    let reach = lattice.cell * 1.5;
    let length = lattice.dims[sweep] - 1;
    let bar = karst_stage::progress::bar(length, "mesher");
    let mut found = Found { sweep, bricks: Window::new(), slabs: Vec::new(), searched: 0, total: 0 };
    let (mut seeds, mut centres, mut up, mut down) =
        (Window::new(), Window::new(), Window::new(), Window::new());
    let (mut live, mut own, mut parts) = (Window::new(), Window::new(), Window::new());
    let mut evaluations = 0;
    let mut vertices = 0u32;
    // The triangles of the last slab resolved; handed over while the workers run the next
    // step's first pass (the sink sees the same calls in the same order).
    let (mut resolved, mut pending) = (Vec::new(), false);
    for t in 0.. {
        evaluations += found.reach(field, &lattice, t);
        bar.set_position(found.searched.min(length));
        if found.searched >= length && t >= found.slabs.len() + 3 {
            break;
        }
        let (bricks, slab) = (&found.bricks, |s: Option<usize>| s.and_then(|s| found.slabs.get(s)).cloned());
        if let Some(r) = slab(Some(t)) {
            let mut evaluated = None;
            rayon::in_place_scope(|scope| {
                scope.spawn(|_| {
                    let values =
                        r.clone().into_par_iter().map(|b| seed_values(field, &lattice, bricks[b])).unzip();
                    evaluated = Some(values);
                });
                hand_over(sink, &resolved, &mut pending)
            })?;
            let (s, c): (Vec<Seeds>, Vec<Seeds>) = evaluated.expect("the scope waits for its task");
            seeds.push(r.start, s);
            centres.push(r.start, c);
            up.push(r.start, slab_neighbours(bricks, sweep, r.clone(), true));
        }
        let previous = slab(t.checked_sub(1));
        if let Some(r) = &previous {
            down.push(r.start, slab_neighbours(bricks, sweep, r.clone(), false));
        }
        let ctx = Context {
            field,
            lattice: &lattice,
            bricks,
            up: &up,
            down: &down,
            seeds: &seeds,
            centres: &centres,
            reach,
            lazy,
        };
        if let Some(r) = previous {
            // The cells of each brick that the seeds and centres do not prove uniform, bit
            // local(i, j, k); then the values each brick needs among its points.
            live.push(r.start, r.clone().into_par_iter().map(|b| live_cells(&ctx, b)).collect());
            let values: Vec<Own> = r
                .clone()
                .into_par_iter()
                .map_init(Scratch::default, |scratch, b| own_values(&ctx, &live, b, scratch))
                .collect();
            // Seeds and centres are in the own values too.
            evaluations += values.iter().map(|o| o.values.len() as u64).sum::<u64>();
            own.push(r.start, values);
        }
        if let Some(r) = slab(t.checked_sub(2)) {
            let mut made: Vec<BrickPart> = r
                .clone()
                .into_par_iter()
                .map_init(Scratch::default, |scratch, b| brick(&ctx, &own, live[b], b, scratch))
                .collect();
            for part in &mut made {
                part.base = vertices;
                vertices += part.slots.len() as u32;
                evaluations += part.evaluations;
            }
            // Gathered (and the bricks' positions freed) by the workers, in brick order.
            let positions: Vec<[f32; 3]> =
                made.par_iter_mut().flat_map_iter(|part| std::mem::take(&mut part.positions)).collect();
            hand_over(sink, &resolved, &mut pending)?;
            sink.vertices(&positions)?;
            parts.push(r.start, made);
        }
        if let Some(r) = slab(t.checked_sub(3)) {
            hand_over(sink, &resolved, &mut pending)?;
            weld(&parts, r, &mut resolved);
            pending = true;
        }
        // What the next step reads: seeds and centres of this slab, upper neighbours, live
        // cells and own values of the previous one, the parts of the one before.
        let first = |s: usize| found.slabs.get(s).map_or(found.total, |r| r.start);
        seeds.keep_from(first(t));
        centres.keep_from(first(t));
        down.keep_from(first(t));
        up.keep_from(first(t.saturating_sub(1)));
        live.keep_from(first(t.saturating_sub(1)));
        own.release_from(first(t.saturating_sub(1)));
        parts.release_from(first(t.saturating_sub(2)));
        let keep = first(t.saturating_sub(1));
        found.bricks.keep_from(keep);
    }
    hand_over(sink, &resolved, &mut pending)?;
    bar.finish_and_clear();
    Ok(evaluations)
}

/// Hands the resolved triangles over to `sink` unless they already were.
fn hand_over<S: MeshSink>(sink: &mut S, resolved: &[[u32; 3]], pending: &mut bool) -> Result<(), S::Error> {
    if std::mem::take(pending) { sink.triangles(resolved) } else { Ok(()) }
}

/// The active bricks, found by the octree one thick slab at a time just ahead of the front.
struct Found {
    sweep: usize,
    /// The bricks the passes may still read, by their index in the order of [`order_key`].
    bricks: Window<[u64; 3]>,
    /// Every slab found so far: its bricks' indices.
    slabs: Vec<Range<usize>>,
    /// Cells along the sweep searched so far.
    searched: u64,
    /// Bricks found so far.
    total: usize,
}

impl Found {
    /// Searches thick slabs until slab `t` and the next one are found (or the lattice ends):
    /// the passes of step t read the neighbours above slab t. Returns the evaluations spent.
    fn reach<V: Volume>(&mut self, field: &V, lattice: &Lattice, t: usize) -> u64 {
        let (sweep, length) = (self.sweep, lattice.dims[self.sweep] - 1);
        let mut evaluations = 0;
        while self.searched < length
            && self.slabs.get(t).is_none_or(|r| self.searched <= self.bricks[r.start][sweep] + BRICK)
        {
            let (bricks, spent) = octree::active_bricks(field, lattice, sweep, self.searched);
            evaluations += spent;
            let start = self.total;
            for slab in bricks.chunk_by(|a, b| a[sweep] == b[sweep]) {
                self.slabs.push(self.total..self.total + slab.len());
                self.total += slab.len();
            }
            self.bricks.push(start, bricks);
            self.searched += THICK;
        }
        evaluations
    }
}

/// Indices of the active bricks next to each brick of `slab`, above them (`upper`) or below.
///
/// Adding an offset to every brick keeps their order (the order key is lexicographic), so the
/// neighbours at one offset are found by one walk along the bricks held, whose position only
/// moves forward: linear in the bricks, where a search per brick and offset was logarithmic.
fn slab_neighbours(
    bricks: &Window<[u64; 3]>,
    sweep: usize,
    slab: Range<usize>,
    upper: bool,
) -> Vec<Neighbours> {
    let end = bricks.first + bricks.items.len();
    let columns: Vec<Vec<u32>> = (1..8usize)
        .into_par_iter()
        .map(|bits| {
            let shift = |at: [u64; 3]| -> Option<[u64; 4]> {
                let mut q = at;
                for (a, x) in q.iter_mut().enumerate() {
                    let step = BRICK * (bits >> a & 1) as u64;
                    *x = if upper { *x + step } else { x.checked_sub(step)? };
                }
                Some(order_key(q, sweep))
            };
            let mut j = if upper { slab.start } else { bricks.first };
            slab.clone()
                .map(|b| {
                    let Some(key) = shift(bricks[b]) else { return u32::MAX };
                    while j < end && order_key(bricks[j], sweep) < key {
                        j += 1;
                    }
                    if j < end && order_key(bricks[j], sweep) == key { j as u32 } else { u32::MAX }
                })
                .collect()
        })
        .collect();
    (0..slab.len()).map(|i| std::array::from_fn(|o| columns[o][i])).collect()
}

/// What the passes over the bricks share.
struct Context<'a, V> {
    field: &'a V,
    lattice: &'a Lattice,
    bricks: &'a Window<[u64; 3]>,
    up: &'a Window<Neighbours>,
    down: &'a Window<Neighbours>,
    seeds: &'a Window<Seeds>,
    centres: &'a Window<Seeds>,
    reach: f64,
    /// False: no cell is proven uniform (every corner evaluated).
    lazy: bool,
}

impl<V> Context<'_, V> {
    /// The brick at offset `bits` above brick `b` (0: b itself), if active.
    fn above(&self, b: usize, bits: usize) -> Option<usize> {
        if bits == 0 {
            Some(b)
        } else {
            Some(self.up[b][bits - 1]).filter(|&n| n != u32::MAX).map(|n| n as usize)
        }
    }
}

fn local(i: usize, j: usize, k: usize) -> usize {
    (k * B + j) * B + i
}

/// The seeds and the centres of brick `at` (one search for the leaves near both).
fn seed_values<V: Volume>(field: &V, lattice: &Lattice, at: [u64; 3]) -> (Seeds, Seeds) {
    let mut out = [[f64::NAN; 8]; 2];
    let mut points = Vec::with_capacity(16);
    let mut slots = Vec::with_capacity(16);
    for (kind, first) in [0, 1].into_iter().enumerate() {
        for s in 0..8 {
            let q = [0, 1, 2].map(|a| at[a] + first + 2 * (s >> a & 1) as u64);
            if (0..3).all(|a| q[a] < lattice.dims[a]) {
                points.push(lattice.point(q));
                slots.push((kind, s));
            }
        }
    }
    let end = [0, 1, 2].map(|a| (at[a] + 3).min(lattice.dims[a] - 1));
    let mut values = Vec::with_capacity(16);
    field.eval_block(lattice.point(at), lattice.point(end), SEED_REACH * lattice.cell, &points, &mut values);
    for ((kind, s), v) in slots.into_iter().zip(values) {
        out[kind][s] = v;
    }
    (out[0], out[1])
}

/// The cells of brick `b` that its seeds and centres do not prove uniform, bit local(i, j, k).
fn live_cells<V>(ctx: &Context<'_, V>, b: usize) -> u64 {
    let (lattice, at) = (ctx.lattice, ctx.bricks[b]);
    let size = [0, 1, 2].map(|a| BRICK.min(lattice.dims[a] - 1 - at[a]) as usize);
    // The seeds of the brick's cells, at local coordinates 0, 2 and 4 along each axis (4: the
    // first seed of the brick above), None where that brick is inactive.
    let seeds: [Option<f64>; 27] = std::array::from_fn(|s| {
        let e = [s % 3, s / 3 % 3, s / 9];
        let bits = (0..3).fold(0, |m, a| m | (e[a] / 2) << a);
        let owner = ctx.above(b, bits)?;
        Some(ctx.seeds[owner][(0..3).fold(0, |m, a| m | (e[a] % 2) << a)])
    });
    let centres = &ctx.centres[b];
    let mut live = 0u64;
    for k in 0..size[2] {
        for j in 0..size[1] {
            for i in 0..size[0] {
                let seed = seeds[i.div_ceil(2) + 3 * j.div_ceil(2) + 9 * k.div_ceil(2)];
                let centre = centres[(i / 2) | (j / 2) << 1 | (k / 2) << 2];
                if !(ctx.lazy && uniform(seed, centre, lattice.cell)) {
                    live |= 1 << local(i, j, k);
                }
            }
        }
    }
    live
}

/// Whether a cell's seed and centre prove it uniform: each of the six other corners gets its
/// sign from the seed or the centre, and those agree (None: the seed's brick is inactive).
fn uniform(seed: Option<f64>, centre: f64, cell: f64) -> bool {
    if seed.is_some_and(|v| v.abs() > DIAGONAL * cell) {
        return true;
    }
    if centre.is_nan() {
        return false;
    }
    if centre.abs() > DIAGONAL * cell {
        return true;
    }
    let Some(seed) = seed else { return false };
    if (seed < 0.0) != (centre < 0.0) {
        return false;
    }
    // Corners one cell from the seed are √2 from the centre, and the other way round.
    let (s, t) = (seed.abs() / cell, centre.abs() / cell);
    s > FACE || t > FACE || (s > EDGE && t > EDGE)
}

/// Bits of the 4³ local points (or cells) whose coordinate along `axis` is 0.
const fn plane_zero(axis: usize) -> u64 {
    let mut mask = 0u64;
    let mut l = 0;
    while l < OWN {
        let x = [l % B, l / B % B, l / (B * B)][axis];
        if x == 0 {
            mask |= 1 << l;
        }
        l += 1;
    }
    mask
}

const PLANE_ZERO: [u64; 3] = [plane_zero(0), plane_zero(1), plane_zero(2)];
/// Local bit strides of the three axes.
const STRIDE: [u32; 3] = [1, B as u32, (B * B) as u32];

/// The points of even and of odd local coordinates: the seeds and the centres.
const SEEDS_AND_CENTRES: u64 = {
    let mut mask = 0u64;
    let mut l = 0;
    while l < OWN {
        let (i, j, k) = (l % B, l / B % B, l / (B * B));
        if (i % 2 == 0 && j % 2 == 0 && k % 2 == 0) || (i % 2 == 1 && j % 2 == 1 && k % 2 == 1) {
            mask |= 1 << l;
        }
        l += 1;
    }
    mask
};

/// The points that are corners of the cells in `cells` (bits local(i, j, k) of one brick),
/// among the points of that brick, moving only along the axes in `axes` (bits x + 2y + 4z).
fn corners_within(cells: u64, axes: usize) -> u64 {
    (0..3).filter(|a| axes >> a & 1 == 1).fold(cells, |m, a| m | ((m << STRIDE[a]) & !PLANE_ZERO[a]))
}

/// The points of brick `b` that are corners of live cells, its own or its lower neighbours'
/// (a cell of the neighbour below along the axes `bits` touches b only through its last plane
/// along them, which lands on b's first plane).
fn corners_of_live_cells(ctx: &Context<'_, impl Sized>, live: &Window<u64>, b: usize) -> u64 {
    let mut points = corners_within(live[b], 7);
    for bits in 1..8usize {
        let n = ctx.down[b][bits - 1];
        if n == u32::MAX {
            continue;
        }
        let moved = (0..3)
            .filter(|a| bits >> a & 1 == 1)
            .fold(live[n as usize], |m, a| (m >> (STRIDE[a] * (B as u32 - 1))) & PLANE_ZERO[a]);
        points |= corners_within(moved, 7 & !bits);
    }
    points
}

/// The values brick `b` needs among the points it owns, [at, at + 4)³: its seeds, and every
/// corner of a cell that the octree keeps (its brick is active) and no seed proves uniform.
/// Any brick polygonizing such a cell finds these values here.
fn own_values<V: Volume>(ctx: &Context<'_, V>, live: &Window<u64>, b: usize, scratch: &mut Scratch) -> Own {
    let (lattice, at) = (ctx.lattice, ctx.bricks[b]);
    let (seeds, centres) = (&ctx.seeds[b], &ctx.centres[b]);
    // Live cells lie inside the lattice, and so do their corners.
    let evaluated = corners_of_live_cells(ctx, live, b) & !SEEDS_AND_CENTRES;
    let Scratch { points, found, .. } = scratch;
    points.clear();
    let mut bits = evaluated;
    while bits != 0 {
        let l = bits.trailing_zeros() as usize;
        bits &= bits - 1;
        points.push(lattice.point([
            at[0] + (l % B) as u64,
            at[1] + (l / B % B) as u64,
            at[2] + (l / (B * B)) as u64,
        ]));
    }
    found.clear();
    if !points.is_empty() {
        let size = [0, 1, 2].map(|a| BRICK.min(lattice.dims[a] - at[a]));
        let end = [0, 1, 2].map(|a| at[a] + size[a] - 1);
        ctx.field.eval_block(lattice.point(at), lattice.point(end), ctx.reach, points, found);
    }
    // Merge the seeds and centres in, in bit order.
    let mut mask = evaluated;
    for s in 0..8 {
        let l = local(2 * (s & 1), (s >> 1 & 1) * 2, (s >> 2 & 1) * 2);
        mask |= (!seeds[s].is_nan() as u64) << l | (!centres[s].is_nan() as u64) << (l + 1 + B + B * B);
    }
    let mut next = found.iter();
    let mut values = Vec::with_capacity(mask.count_ones() as usize);
    let mut bits = mask;
    while bits != 0 {
        let l = bits.trailing_zeros() as usize;
        bits &= bits - 1;
        let (i, j, k) = (l % B, l / B % B, l / (B * B));
        let s = (i / 2) | ((j / 2) << 1) | ((k / 2) << 2);
        values.push(if evaluated >> l & 1 == 1 {
            *next.next().expect("one value per point")
        } else if i % 2 == 0 {
            seeds[s]
        } else {
            centres[s]
        });
    }
    Own { mask, values }
}

/// Buffers a thread reuses from brick to brick (every brick overwrites what it reads).
#[derive(Default)]
struct Scratch {
    values: Vec<f64>,
    needed: Vec<bool>,
    made: Vec<bool>,
    missing: Vec<(usize, usize, usize)>,
    points: Vec<DVec3>,
    found: Vec<f64>,
    positions: Vec<(u16, [f32; 3])>,
    triangles: Vec<[VertexRef; 3]>,
    rank: Vec<u16>,
}

fn brick<V: Volume>(
    ctx: &Context<'_, V>,
    own: &Window<Own>,
    live: u64,
    b: usize,
    scratch: &mut Scratch,
) -> BrickPart {
    let (field, lattice, at) = (ctx.field, ctx.lattice, ctx.bricks[b]);
    let n = N;
    let size = [0, 1, 2].map(|a| (BRICK + 1).min(lattice.dims[a] - at[a]) as usize);
    let index = |i: usize, j: usize, k: usize| (k * n + j) * n + i;
    let Scratch {
        values,
        needed,
        made,
        missing,
        points,
        found,
        positions: positions_by_slot,
        triangles,
        rank,
    } = scratch;
    // The corners of the live cells.
    needed.clear();
    needed.resize(n * n * n, false);
    for k in 0..size[2].saturating_sub(1) {
        for j in 0..size[1].saturating_sub(1) {
            for i in 0..size[0].saturating_sub(1) {
                if live >> local(i, j, k) & 1 == 1 {
                    for d in 0..8 {
                        needed[index(i + (d & 1), j + (d >> 1 & 1), k + (d >> 2 & 1))] = true;
                    }
                }
            }
        }
    }
    values.clear();
    values.resize(n * n * n, f64::NAN);
    missing.clear();
    let owners: [Option<&Own>; 8] = std::array::from_fn(|bits| ctx.above(b, bits).map(|o| &own[o]));
    for k in 0..size[2] {
        for j in 0..size[1] {
            for i in 0..size[0] {
                if !needed[index(i, j, k)] {
                    continue;
                }
                let bits = (i / B) | (j / B) << 1 | (k / B) << 2;
                match owners[bits] {
                    Some(o) => {
                        values[index(i, j, k)] =
                            o.get(local(i % B, j % B, k % B)).expect("the owner evaluated a needed point")
                    }
                    None => missing.push((i, j, k)),
                }
            }
        }
    }
    let mut evaluations = 0;
    if !missing.is_empty() {
        points.clear();
        points.extend(
            missing
                .iter()
                .map(|&(i, j, k)| lattice.point([at[0] + i as u64, at[1] + j as u64, at[2] + k as u64])),
        );
        let end = [0, 1, 2].map(|a| at[a] + size[a] as u64 - 1);
        found.clear();
        field.eval_block(lattice.point(at), lattice.point(end), ctx.reach, points, found);
        for (&(i, j, k), &v) in missing.iter().zip(found.iter()) {
            values[index(i, j, k)] = v;
        }
        evaluations = missing.len() as u64;
    }

    // The vertex of a crossed edge belongs to the brick of the canonical cell of that edge:
    // among the (up to four) cells around it, the one with the highest coordinates. That cell
    // is crossed by the surface, so its brick is active and makes the vertex; relative to any
    // other cell of the edge it is this brick or an upper neighbour.
    let last = [0, 1, 2].map(|a| lattice.dims[a] - 1);
    // Away from the lattice's last points the references depend only on the cell and the edge.
    let interior = (0..3).all(|d| at[d] + BRICK < last[d]).then(interior_refs);
    made.clear();
    made.resize(SLOTS, false);
    positions_by_slot.clear();
    triangles.clear();
    let cases = table();
    for k in 0..size[2].saturating_sub(1) {
        for j in 0..size[1].saturating_sub(1) {
            for i in 0..size[0].saturating_sub(1) {
                if live >> local(i, j, k) & 1 == 0 {
                    continue;
                }
                let corner = |c: usize| [i + (c & 1), j + (c >> 1 & 1), k + (c >> 2 & 1)];
                let first = index(i, j, k);
                let v: [f64; 8] = std::array::from_fn(|c| values[first + CORNER_OFFSETS[c]]);
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
                        let r = match interior {
                            Some(refs) => refs[local(i, j, k) * 12 + e],
                            None => edge_ref(corner(EDGES[e].0), e, at, last),
                        };
                        let slot = (r & ((1 << SLOT_BITS) - 1)) as usize;
                        if r >> SLOT_BITS == 0 && !made[slot] {
                            made[slot] = true;
                            positions_by_slot.push((slot as u16, edge_position(e).as_vec3().to_array()));
                        }
                        r
                    }));
                }
            }
        }
    }
    positions_by_slot.sort_unstable_by_key(|&(slot, _)| slot);
    // The brick's own vertices are named by their rank from here on: the weld only searches
    // the slots of the neighbours'.
    rank.resize(SLOTS, 0);
    for (r, &(slot, _)) in positions_by_slot.iter().enumerate() {
        rank[slot as usize] = r as u16;
    }
    for r in triangles.iter_mut().flatten() {
        if *r >> SLOT_BITS == 0 {
            *r = rank[*r as usize];
        }
    }
    BrickPart {
        slots: positions_by_slot.iter().map(|&(s, _)| s).collect(),
        positions: positions_by_slot.iter().map(|&(_, p)| p).collect(),
        // Exactly sized: the parts of two slabs are alive together.
        triangles: triangles.clone(),
        neighbours: ctx.up[b],
        base: 0,
        evaluations,
    }
}

/// Offsets in a brick's corner values (x fastest, N per row) of the 8 corners of a cell from its
/// first one, by corner bits x + 2y + 4z.
const CORNER_OFFSETS: [usize; 8] = [0, 1, N, N + 1, N * N, N * N + 1, N * N + N, N * N + N + 1];

/// The vertex on cell edge `e` whose lower point is `q` (local to the brick at `at`; `last`: the
/// lattice's last point on each axis): owned by the brick of the edge's canonical cell, the
/// highest of the cells around the edge (lower on an axis where the edge lies on the lattice's
/// last plane), which is this brick or an upper neighbour.
fn edge_ref(q: [usize; 3], e: usize, at: [u64; 3], last: [u64; 3]) -> VertexRef {
    let (a, c) = EDGES[e];
    let axis = (c - a).trailing_zeros() as usize;
    let cell = |d: usize| if d != axis && at[d] + q[d] as u64 == last[d] { q[d] - 1 } else { q[d] };
    let bits = (cell(0) / B) | (cell(1) / B) << 1 | (cell(2) / B) << 2;
    let o = [0, 1, 2].map(|d| q[d] - B * (bits >> d & 1));
    let slot = axis * N * N * N + (o[2] * N + o[1]) * N + o[0];
    ((bits as u16) << SLOT_BITS) | slot as u16
}

/// [`edge_ref`] of every edge of every cell of a brick away from the lattice's last points, by
/// local(i, j, k) · 12 + edge.
fn interior_refs() -> &'static [VertexRef] {
    static REFS: std::sync::OnceLock<Vec<VertexRef>> = std::sync::OnceLock::new();
    REFS.get_or_init(|| {
        (0..OWN * 12)
            .map(|r| {
                let (l, e) = (r / 12, r % 12);
                let a = EDGES[e].0;
                let q = [l % B + (a & 1), l / B % B + (a >> 1 & 1), l / (B * B) + (a >> 2 & 1)];
                edge_ref(q, e, [0; 3], [u64::MAX; 3])
            })
            .collect()
    })
}

/// Resolves the triangles of the bricks in `slab` to vertex numbers, into `out`: a vertex is
/// its owner's base plus its rank among the owner's slots (the owner is the brick or an upper
/// neighbour, in this slab or the next).
fn weld(parts: &Window<BrickPart>, slab: Range<usize>, out: &mut Vec<[u32; 3]>) {
    let resolve = |b: usize, r: VertexRef| -> u32 {
        let (bits, slot) = ((r >> SLOT_BITS) as usize, r & ((1 << SLOT_BITS) - 1));
        if bits == 0 {
            return parts[b].base + slot as u32;
        }
        let owner = &parts[parts[b].neighbours[bits - 1] as usize];
        owner.base + owner.slots.binary_search(&slot).expect("the owner made the vertex") as u32
    };
    // Each brick resolves its triangles into its own range of the output.
    out.clear();
    out.resize(slab.clone().map(|b| parts[b].triangles.len()).sum(), [0; 3]);
    let mut ranges = Vec::with_capacity(slab.len());
    let mut rest = out.as_mut_slice();
    for b in slab {
        let (range, tail) = rest.split_at_mut(parts[b].triangles.len());
        ranges.push((b, range));
        rest = tail;
    }
    ranges.into_par_iter().for_each(|(b, range)| {
        for (out, t) in range.iter_mut().zip(&parts[b].triangles) {
            *out = t.map(|r| resolve(b, r));
        }
    });
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A union of spheres (exact distance, 1-Lipschitz) with surfaces at every angle and some
    /// thinner than a cell.
    struct Spheres(Vec<(DVec3, f64)>);

    impl Volume for Spheres {
        fn eval(&self, p: DVec3) -> f64 {
            self.0.iter().map(|&(c, r)| (p - c).length() - r).fold(f64::INFINITY, f64::min)
        }

        fn extent(&self) -> (DVec3, DVec3) {
            (DVec3::ZERO, DVec3::splat(20.0))
        }
    }

    fn spheres() -> Spheres {
        let mut state = 7u64;
        let mut next = || {
            state = state.wrapping_mul(6_364_136_223_846_793_005).wrapping_add(1_442_695_040_888_963_407);
            (state >> 11) as f64 / (1u64 << 53) as f64
        };
        Spheres(
            (0..40)
                .map(|_| (DVec3::new(next(), next(), next()) * 16.0 + DVec3::splat(2.0), 0.2 + 2.5 * next()))
                .collect(),
        )
    }

    /// The mesh of `field` at `cell`, lazy or not, along the given sweep axis.
    fn mesh(field: &impl Volume, cell: f64, lazy: bool, sweep: Option<usize>) -> TriMesh {
        let mut mesh = TriMesh::default();
        let Ok(evaluations) = polygonize_with(field, cell, lazy, sweep, &mut mesh);
        mesh.field_evaluations = evaluations;
        mesh
    }

    #[test]
    fn lazy_corners_give_the_mesh_of_all_corners_with_fewer_evaluations() {
        let field = spheres();
        for cell in [0.5, 0.37] {
            let lazy = mesh(&field, cell, true, None);
            let all = mesh(&field, cell, false, None);
            assert!(lazy.triangles.len() > 1000);
            assert_eq!(lazy.vertices, all.vertices);
            assert_eq!(lazy.triangles, all.triangles);
            assert!(
                lazy.field_evaluations * 3 < all.field_evaluations * 2,
                "{} vs {}",
                lazy.field_evaluations,
                all.field_evaluations
            );
            assert!(lazy.evaluations_per_vertex() < 4.5, "{}", lazy.evaluations_per_vertex());
        }
    }

    /// A sink that refuses a triangle naming a vertex not given yet.
    #[derive(Default)]
    struct Checked {
        vertices: usize,
        pieces: usize,
    }

    impl MeshSink for Checked {
        type Error = String;

        fn vertices(&mut self, vertices: &[[f32; 3]]) -> Result<(), String> {
            self.vertices += vertices.len();
            Ok(())
        }

        fn triangles(&mut self, triangles: &[[u32; 3]]) -> Result<(), String> {
            self.pieces += 1;
            match triangles.iter().flatten().find(|&&v| v as usize >= self.vertices) {
                Some(v) => Err(format!("vertex {v} named before it was given ({} given)", self.vertices)),
                None => Ok(()),
            }
        }
    }

    #[test]
    fn every_sweep_axis_gives_the_same_surface_handed_over_in_slabs() {
        let field = spheres();
        // The triangles by their corners' positions, whatever the numbering of the vertices.
        let surface = |m: &TriMesh| {
            let mut corners: Vec<[[u32; 3]; 3]> =
                m.triangles.iter().map(|t| t.map(|v| m.vertices[v as usize].map(f32::to_bits))).collect();
            corners.sort_unstable();
            corners
        };
        let along_z = mesh(&field, 0.5, true, Some(2));
        assert!(along_z.triangles.len() > 1000);
        for sweep in [0, 1] {
            let other = mesh(&field, 0.5, true, Some(sweep));
            assert_ne!(other.triangles, along_z.triangles, "the numbering follows the sweep");
            assert_eq!(surface(&other), surface(&along_z));
        }
        let mut checked = Checked::default();
        polygonize_with(&field, 0.5, true, None, &mut checked).unwrap();
        assert_eq!(checked.vertices, along_z.vertices.len());
        // 20 m at 0.5 m: about 11 slabs of 4 cells.
        assert!(checked.pieces > 5, "{} pieces", checked.pieces);
    }
}
