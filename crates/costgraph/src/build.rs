//! Building the cost graph: k nearest neighbours, optional symmetrisation, the input checks,
//! then the cost of every edge in every cost set with the distributions of its terms.
//!
//! Work is split into fixed chunks of consecutive nodes ([`knn::CHUNK`]) whose results are
//! concatenated in chunk order, so the graph is byte-identical whatever the number of threads.
//! The samples come in Morton order, so a chunk of consecutive nodes is a compact region whose
//! neighbours' data stays in cache; and a chunk's rows are one range of every array (in the
//! later cost sets too: their own rows are consecutive in node order), so each chunk writes
//! into slices of its own.

use rayon::prelude::*;

use karst_geology::Scene;
use karst_sampling::Samples;

use crate::cost::{CostModel, EdgeTerms, NodeFields};
use crate::knn::{self, CHUNK, Rows, chunk_nodes};
use crate::payload::{CostGraph, CostSet, SHARED_ROW};
use crate::stats::{Histogram, SetStats, Summary, TermStats};
use crate::{CostGraphError, checks};

/// Builds the cost graph of `samples` under `scene`'s geology, with every input check.
pub fn build(scene: &Scene, samples: &Samples) -> Result<CostGraph, CostGraphError> {
    let k = scene.costgraph().k;
    if k >= samples.len() {
        return Err(CostGraphError::TooFewSamples { k, samples: samples.len() });
    }
    let model = CostModel::from_scene(scene);
    crate::estimate::check(scene, samples.len(), model.set_count())?;
    let chunks = samples.len().div_ceil(CHUNK) as u64;
    let bar = karst_stage::progress::bar(2 * chunks, "costgraph");
    let done = || bar.inc(1);
    let rows = edges(scene, &samples.positions, &done);
    checks::isolated_keypoints(scene, samples, &rows)?;
    checks::sinks_reach_their_springs(scene, samples, &rows)?;
    let graph = costed(&model, &samples.positions, rows, &done);
    bar.finish_and_clear();
    graph
}

/// The cost graph of bare `points` (no key-point checks): what `cargo xtask bench` times. Any
/// order of the points gives the same graph; points stored along a space-filling curve, as
/// samples are, give it fastest.
pub fn build_points(scene: &Scene, points: &[[f64; 3]]) -> Result<CostGraph, CostGraphError> {
    let rows = edges(scene, points, &|| ());
    costed(&CostModel::from_scene(scene), points, rows, &|| ())
}

/// The edges: k nearest neighbours within the maximum length, symmetrised when asked.
fn edges(scene: &Scene, points: &[[f64; 3]], done: &(dyn Fn() + Sync)) -> Rows {
    let p = scene.costgraph();
    let rows = knn::neighbours(points, (p.k, p.max_edge_length), done);
    if p.symmetrise { rows.symmetrised() } else { rows }
}

/// The distributions are taken over the edges of every `STATS_STRIDE`-th node: a systematic
/// sample of an eighth of the edges describes them as well as all do, at an eighth of the cost.
const STATS_STRIDE: usize = 8;

/// What one chunk of nodes contributes besides its costs (written in place): the least cost
/// per metre per set, a sample of edge lengths, the term distributions.
struct ChunkCosts {
    least_per_metre: Vec<f64>,
    lengths: Vec<f64>,
    sets: Vec<SetStats>,
}

/// Costs every edge of `rows` under `model`, in chunks of consecutive nodes.
fn costed(
    model: &CostModel,
    points: &[[f64; 3]],
    rows: Rows,
    done: &(dyn Fn() + Sync),
) -> Result<CostGraph, CostGraphError> {
    let fields = model.node_fields(points);
    let empty = empty_sets(model);
    let (own_rows, own_edges) = own_rows(model, &fields, &rows);
    let mut arrays: Vec<Vec<f32>> = (0..model.set_count())
        .map(|s| vec![0f32; if s == 0 { rows.targets.len() } else { own_edges }])
        .collect();
    let places = chunk_places(&rows, &own_rows);
    let chunks: Vec<Result<ChunkCosts, CostGraphError>> = split_by_chunk(&mut arrays, &places)
        .into_par_iter()
        .enumerate()
        .map(|(c, costs)| {
            let nodes = chunk_nodes(c, rows.node_count());
            let place = ChunkPlace { first_edge: places[c].0, first_own: places[c].1, costs };
            let chunk = cost_chunk(model, &fields, (&rows, &own_rows), nodes, (&empty, place));
            done();
            chunk
        })
        .collect();
    let chunks: Vec<ChunkCosts> = chunks.into_iter().collect::<Result<_, _>>()?;
    let longest = chunks.iter().flat_map(|c| &c.lengths).copied().fold(0.0, f64::max);
    let mut summary =
        Summary { model: model.name().into(), lengths: Some(Histogram::new(0.0, longest)), sets: empty };
    let cost_sets = model
        .set_water_tables()
        .into_iter()
        .zip(arrays)
        .enumerate()
        .map(|(s, (water_table, costs))| {
            let least = chunks.iter().map(|c| c.least_per_metre[s]).fold(f64::INFINITY, f64::min);
            CostSet {
                water_table,
                costs,
                min_cost_per_metre: Some(if least.is_finite() { least } else { 0.0 }),
            }
        })
        .collect();
    for chunk in &chunks {
        merge(&mut summary, chunk);
    }
    Ok(CostGraph { offsets: rows.offsets, targets: rows.targets, own_rows, cost_sets, summary })
}

/// With several cost sets, where each node's row starts among the rows the later sets store
/// apart ([`SHARED_ROW`] when every edge of the row costs the same in every set), and how many
/// edges those rows hold; nothing with one set.
fn own_rows(model: &CostModel, fields: &NodeFields, rows: &Rows) -> (Vec<u32>, usize) {
    if model.set_count() <= 1 {
        return (Vec::new(), 0);
    }
    let sharing = model.sharing(fields);
    let shared: Vec<bool> = (0..rows.node_count())
        .into_par_iter()
        .with_min_len(CHUNK)
        .map(|i| rows.row(i).iter().all(|&j| sharing[i] & sharing[j as usize] != 0))
        .collect();
    let mut next = 0usize;
    let starts = shared
        .iter()
        .enumerate()
        .map(|(i, &shared)| {
            if shared {
                return SHARED_ROW;
            }
            let start = next as u32;
            next += rows.row(i).len();
            start
        })
        .collect();
    (starts, next)
}

/// Where a chunk's costs go: its slice of every set's array (its rows in set 0, its own rows in
/// the later sets), and the array indices at which those slices start.
struct ChunkPlace<'c> {
    first_edge: usize,
    first_own: usize,
    costs: Vec<&'c mut [f32]>,
}

/// Per chunk of [`CHUNK`] nodes, the index of its first edge and of its first edge among the
/// later sets' own rows.
fn chunk_places(rows: &Rows, own_rows: &[u32]) -> Vec<(usize, usize)> {
    let chunks = rows.node_count().div_ceil(CHUNK);
    let own_edges: Vec<usize> = (0..chunks)
        .into_par_iter()
        .map(|c| {
            chunk_nodes(c, rows.node_count())
                .filter(|&i| own_rows.get(i).is_some_and(|&start| start != SHARED_ROW))
                .map(|i| rows.row(i).len())
                .sum()
        })
        .collect();
    let mut first_own = 0;
    (0..chunks)
        .map(|c| {
            let place = (rows.offsets[c * CHUNK] as usize, first_own);
            first_own += own_edges[c];
            place
        })
        .collect()
}

/// Splits every set's array into the chunks' slices ([`chunk_places`]): per chunk, one slice
/// per set.
fn split_by_chunk<'c>(arrays: &'c mut [Vec<f32>], places: &[(usize, usize)]) -> Vec<Vec<&'c mut [f32]>> {
    let mut per_chunk: Vec<Vec<&mut [f32]>> = places.iter().map(|_| Vec::new()).collect();
    for (set, array) in arrays.iter_mut().enumerate() {
        let first = |&(edge, own): &(usize, usize)| if set == 0 { edge } else { own };
        let ends = places.iter().skip(1).map(first).chain([array.len()]);
        let mut rest: &mut [f32] = array;
        let mut taken = 0;
        for (chunk, end) in per_chunk.iter_mut().zip(ends) {
            let (slice, tail) = std::mem::take(&mut rest).split_at_mut(end - taken);
            chunk.push(slice);
            rest = tail;
            taken = end;
        }
    }
    per_chunk
}

fn cost_chunk(
    model: &CostModel,
    fields: &NodeFields,
    (rows, own_rows): (&Rows, &[u32]),
    nodes: std::ops::Range<usize>,
    (sets, mut place): (&[SetStats], ChunkPlace),
) -> Result<ChunkCosts, CostGraphError> {
    let edges = (rows.offsets[nodes.end] - rows.offsets[nodes.start]) as usize;
    let mut out = ChunkCosts {
        least_per_metre: vec![f64::INFINITY; model.set_count()],
        lengths: Vec::with_capacity(edges / STATS_STRIDE + 1),
        sets: sets.to_vec(),
    };
    let mut terms = EdgeTerms::default();
    for i in nodes {
        let first = rows.offsets[i] as usize - place.first_edge;
        let own = own_rows.get(i).copied().filter(|&start| start != SHARED_ROW);
        for (column, &j) in rows.row(i).iter().enumerate() {
            model.edge(fields, i, j as usize, &mut terms);
            for (set, (least, &cost)) in out.least_per_metre.iter_mut().zip(&terms.cost).enumerate() {
                // Caught where it happens: the artifact's costs are f32, finite and > 0.
                let stored = cost as f32;
                if !(stored.is_finite() && stored > 0.0) {
                    return Err(CostGraphError::CostOutOfRange { cost, length: terms.length });
                }
                match (set, own) {
                    (0, _) => place.costs[0][first + column] = stored,
                    (_, Some(start)) => place.costs[set][start as usize - place.first_own + column] = stored,
                    (_, None) => {
                        debug_assert_eq!(stored.to_bits(), (terms.cost[0] as f32).to_bits(), "shared row {i}")
                    }
                }
                // As the searches would measure it: the stored cost over the length.
                if terms.length > 0.0 {
                    *least = least.min(f64::from(stored) / terms.length);
                }
            }
            if !i.is_multiple_of(STATS_STRIDE) {
                continue;
            }
            out.lengths.push(terms.length);
            for (s, set) in out.sets.iter_mut().enumerate() {
                set.cost_per_metre.add(terms.cost[s] / terms.length);
                let (values, count) = terms.values(s);
                for (stats, value) in set.terms.iter_mut().zip(&values[..count]) {
                    stats.histogram.add(*value);
                }
            }
        }
    }
    Ok(out)
}

/// Empty term histograms over [0, 1] and cost-per-metre histograms over [ε, its largest
/// possible value], one set per cost set.
fn empty_sets(model: &CostModel) -> Vec<SetStats> {
    let terms = model.terms();
    let (floor, top) = model.cost_per_metre_range();
    model
        .set_water_tables()
        .into_iter()
        .map(|water_table| SetStats {
            water_table,
            terms: terms
                .iter()
                .map(|&(name, weight)| TermStats {
                    name: name.into(),
                    weight,
                    histogram: Histogram::new(0.0, 1.0),
                })
                .collect(),
            cost_per_metre: Histogram::new(floor, top),
        })
        .collect()
}

fn merge(summary: &mut Summary, chunk: &ChunkCosts) {
    if let Some(lengths) = &mut summary.lengths {
        for &length in &chunk.lengths {
            lengths.add(length);
        }
    }
    for (all, part) in summary.sets.iter_mut().zip(&chunk.sets) {
        all.cost_per_metre.merge(&part.cost_per_metre);
        for (a, b) in all.terms.iter_mut().zip(&part.terms) {
            a.histogram.merge(&b.histogram);
        }
    }
}
