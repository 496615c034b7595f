//! Building the cost graph: k nearest neighbours, optional symmetrisation, the input checks,
//! then what the costs need: the rows each later cost set holds apart, the check that every
//! cost of the model fits, the least cost per metre of every set and the distributions of the
//! costs over a systematic sample of the edges. The costs themselves are made later, for the
//! rows the searches read (`costs.rs`).
//!
//! Work is split into fixed chunks of consecutive nodes ([`knn::CHUNK`]) whose results are
//! concatenated in chunk order, so the graph is byte-identical whatever the number of threads.
//! The samples come in Morton order, so a chunk of consecutive nodes is a compact region whose
//! neighbours' data stays in cache.

use rayon::prelude::*;

use karst_sampling::Samples;
use karst_scene::SceneView;
use karst_scene::params::CostgraphParams;

use crate::cost::{CostModel, EdgeTerms, NodeFields};
use crate::costs::SHARED_ROW;
use crate::knn::{self, CHUNK, Rows, chunk_nodes};
use crate::payload::{CostGraph, CostSet};
use crate::stats::{Histogram, SetStats, Summary, TermStats};
use crate::view::CostgraphView;
use crate::{CostGraphError, checks};

/// Builds the cost graph of `samples` under the scene's geology, with every input check.
pub fn build(view: &CostgraphView, samples: &Samples) -> Result<CostGraph, CostGraphError> {
    let k = view.costgraph.k;
    if k >= samples.len() {
        return Err(CostGraphError::TooFewSamples { k, samples: samples.len() });
    }
    checks::tags_of_the_scene(view, samples)?;
    let model = CostModel::new(view);
    crate::estimate::check(view, samples.len(), model.set_count())?;
    let chunks = samples.len().div_ceil(CHUNK) as u64;
    let bar = karst_stage::progress::bar(2 * chunks, "costgraph");
    let done = || bar.inc(1);
    let (rows, lengths) = edges(view.costgraph, &samples.positions, &done);
    checks::isolated_keypoints(view, samples, &rows)?;
    checks::sinks_reach_their_springs(view, samples, &rows)?;
    let graph = graph_of(view, &model, &samples.positions, (rows, lengths), &done);
    bar.finish_and_clear();
    graph
}

/// The cost graph of bare `points` (no key-point checks): what `cargo xtask bench` times. Any
/// order of the points gives the same graph; points stored along a space-filling curve, as
/// samples are, give it fastest.
pub fn build_points(view: &CostgraphView, points: &[[f64; 3]]) -> Result<CostGraph, CostGraphError> {
    let edges = edges(view.costgraph, points, &|| ());
    graph_of(view, &CostModel::new(view), points, edges, &|| ())
}

/// The edges: k nearest neighbours within the maximum length, symmetrised when asked, and the
/// shortest and longest edge's lengths.
fn edges(p: &CostgraphParams, points: &[[f64; 3]], done: &(dyn Fn() + Sync)) -> (Rows, Option<(f64, f64)>) {
    let rows = knn::neighbours(points, (p.k, p.max_edge_length), done);
    // A reversed edge j → i added by the symmetrisation is as long as i → j, which lies within
    // the lengths of the neighbours' rows.
    let lengths = length_range(points, &rows);
    (if p.symmetrise { rows.symmetrised() } else { rows }, lengths)
}

/// The shortest and the longest edge of nearest-first rows (None without edges): the first
/// and the last of each row.
fn length_range(points: &[[f64; 3]], rows: &Rows) -> Option<(f64, f64)> {
    (0..rows.node_count())
        .into_par_iter()
        .with_min_len(CHUNK)
        .filter_map(|i| {
            let row = rows.row(i);
            let length = |j: &u32| crate::grid::distance2(&points[i], &points[*j as usize]).sqrt();
            Some((length(row.first()?), length(row.last()?)))
        })
        .reduce_with(|a, b| (a.0.min(b.0), a.1.max(b.1)))
}

/// The relative margin of the least cost per metre under the model's bound: a stored cost is
/// the f32 nearest its f64 value (within 2⁻²⁴ of it), and the searches compare it with the
/// bound times distances computed in f64.
const BOUND_MARGIN: f64 = 8.0 * f32::EPSILON as f64;

/// The graph of `rows` under `model`: the rows each later set holds apart, every set's bound,
/// the distributions of a sample of the costs. Refuses a model some of whose costs would not
/// be finite f32 > 0.
fn graph_of(
    view: &CostgraphView,
    model: &CostModel,
    points: &[[f64; 3]],
    (rows, lengths): (Rows, Option<(f64, f64)>),
    done: &(dyn Fn() + Sync),
) -> Result<CostGraph, CostGraphError> {
    if let Some(lengths) = lengths {
        costs_fit(model, lengths)?;
    }
    let fields = model.node_fields(points);
    let own_rows = own_rows(model, &fields, &rows);
    let summary = summary(model, &fields, &rows, done);
    let least = model.least_cost_per_metre() * (1.0 - BOUND_MARGIN);
    let cost_sets = model
        .set_water_tables()
        .into_iter()
        .map(|water_table| CostSet { water_table, min_cost_per_metre: Some(least) })
        .collect();
    let made_under = view.sections_hash();
    Ok(CostGraph::uncosted((rows.offsets, rows.targets, own_rows), cost_sets, made_under, summary))
}

/// Whether every cost of `model` on edges of `lengths` (shortest, longest) is a finite f32 > 0:
/// each lies between the least cost per metre times the shortest length and the largest times
/// the longest.
fn costs_fit(model: &CostModel, (shortest, longest): (f64, f64)) -> Result<(), CostGraphError> {
    let most = model.cost_per_metre_range().1;
    for (cost, length) in [(model.least_cost_per_metre() * shortest, shortest), (most * longest, longest)] {
        let stored = cost as f32;
        if !(stored.is_finite() && stored > 0.0) {
            return Err(CostGraphError::CostOutOfRange { cost, length });
        }
    }
    Ok(())
}

/// With several cost sets, where each node's row starts among the rows the later sets hold
/// apart ([`SHARED_ROW`] when every edge of the row costs the same in every set); nothing with
/// one set.
fn own_rows(model: &CostModel, fields: &NodeFields, rows: &Rows) -> Vec<u32> {
    if model.set_count() <= 1 {
        return Vec::new();
    }
    let sharing = model.sharing(fields);
    let shared: Vec<bool> = (0..rows.node_count())
        .into_par_iter()
        .with_min_len(CHUNK)
        .map(|i| rows.row(i).iter().all(|&j| sharing[i] & sharing[j as usize] != 0))
        .collect();
    let mut next = 0usize;
    shared
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
        .collect()
}

/// The distributions are taken over the rows of every `stride`-th node, `stride` the smallest
/// that leaves at most this many edges: a systematic sample of a quarter million edges
/// describes a graph as well as all of its edges do, and only these are costed here.
const STATS_EDGES: usize = 1 << 18;

/// What one chunk of nodes contributes to the distributions: its sample of edge lengths and
/// the term distributions.
struct ChunkStats {
    lengths: Vec<f64>,
    sets: Vec<SetStats>,
}

/// The distributions of the edge lengths and of every cost term over the sampled rows.
fn summary(model: &CostModel, fields: &NodeFields, rows: &Rows, done: &(dyn Fn() + Sync)) -> Summary {
    let empty = empty_sets(model);
    let stride = rows.targets.len().div_ceil(STATS_EDGES).max(1);
    let chunks: Vec<ChunkStats> = (0..rows.node_count().div_ceil(CHUNK))
        .into_par_iter()
        .map(|c| {
            let nodes = chunk_nodes(c, rows.node_count()).filter(|i| i.is_multiple_of(stride));
            let chunk = chunk_stats(model, fields, rows, nodes, &empty);
            done();
            chunk
        })
        .collect();
    let longest = chunks.iter().flat_map(|c| &c.lengths).copied().fold(0.0, f64::max);
    let mut summary =
        Summary { model: model.name().into(), lengths: Some(Histogram::new(0.0, longest)), sets: empty };
    for chunk in &chunks {
        merge(&mut summary, chunk);
    }
    summary
}

/// Costs the rows of `nodes` for the distributions.
fn chunk_stats(
    model: &CostModel,
    fields: &NodeFields,
    rows: &Rows,
    nodes: impl Iterator<Item = usize>,
    sets: &[SetStats],
) -> ChunkStats {
    let mut out = ChunkStats { lengths: Vec::new(), sets: sets.to_vec() };
    let mut terms = EdgeTerms::default();
    for i in nodes {
        for &j in rows.row(i) {
            model.edge(fields, i, j as usize, &mut terms);
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
    out
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

fn merge(summary: &mut Summary, chunk: &ChunkStats) {
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
