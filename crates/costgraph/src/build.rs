//! Building the cost graph: k nearest neighbours, optional symmetrisation, the input checks,
//! then the cost of every edge in every cost set with the distributions of its terms.
//!
//! Work is split into fixed chunks of nodes ([`knn::CHUNK`]) whose results are concatenated in
//! chunk order, so the graph is byte-identical whatever the number of threads.

use rayon::prelude::*;

use karst_geology::Scene;
use karst_sampling::Samples;

use crate::cost::{CostModel, EdgeTerms, NodeFields};
use crate::knn::{self, CHUNK, Rows};
use crate::payload::{CostGraph, CostSet};
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
    let order = knn::spatial_order(&samples.positions);
    let rows = edges(scene, &samples.positions, &order, &done);
    checks::isolated_keypoints(scene, samples, &rows)?;
    checks::sinks_reach_their_springs(scene, samples, &rows)?;
    let graph = costed(&model, &samples.positions, (rows, &order), &done);
    bar.finish_and_clear();
    graph
}

/// The cost graph of bare `points` (no key-point checks): what `cargo xtask bench` times.
pub fn build_points(scene: &Scene, points: &[[f64; 3]]) -> Result<CostGraph, CostGraphError> {
    let order = knn::spatial_order(points);
    let rows = edges(scene, points, &order, &|| ());
    costed(&CostModel::from_scene(scene), points, (rows, &order), &|| ())
}

/// The edges: k nearest neighbours within the maximum length, symmetrised when asked.
fn edges(scene: &Scene, points: &[[f64; 3]], order: &[u32], done: &(dyn Fn() + Sync)) -> Rows {
    let p = scene.costgraph();
    let rows = knn::neighbours(points, order, (p.k, p.max_edge_length), done);
    if p.symmetrise { rows.symmetrised() } else { rows }
}

/// The distributions are taken over the edges of every `STATS_STRIDE`-th node: a systematic
/// sample of an eighth of the edges describes them as well as all do, at an eighth of the cost.
const STATS_STRIDE: usize = 8;

/// What one chunk of nodes contributes: costs per set row by row, a sample of edge lengths,
/// the term distributions.
struct ChunkCosts {
    costs: Vec<Vec<f32>>,
    lengths: Vec<f64>,
    sets: Vec<SetStats>,
}

/// Costs every edge of `rows` under `model`, in chunks of nodes in spatial order.
fn costed(
    model: &CostModel,
    points: &[[f64; 3]],
    (rows, order): (Rows, &[u32]),
    done: &(dyn Fn() + Sync),
) -> Result<CostGraph, CostGraphError> {
    let fields = model.node_fields(points);
    let empty = empty_sets(model);
    let chunks: Vec<Result<ChunkCosts, CostGraphError>> = order
        .par_chunks(CHUNK)
        .map(|chunk| {
            let costs = cost_chunk(model, &fields, &rows, chunk, &empty);
            done();
            costs
        })
        .collect();
    let chunks: Vec<ChunkCosts> = chunks.into_iter().collect::<Result<_, _>>()?;
    let longest = chunks.iter().flat_map(|c| &c.lengths).copied().fold(0.0, f64::max);
    let mut summary =
        Summary { model: model.name().into(), lengths: Some(Histogram::new(0.0, longest)), sets: empty };
    let cost_sets = model
        .set_water_tables()
        .into_iter()
        .enumerate()
        .map(|(s, water_table)| {
            let mut costs = vec![0f32; rows.targets.len()];
            knn::scatter(order, &rows.offsets, chunks.iter().map(|c| c.costs[s].as_slice()), &mut costs);
            CostSet { water_table, costs }
        })
        .collect();
    for chunk in &chunks {
        merge(&mut summary, chunk);
    }
    Ok(CostGraph { offsets: rows.offsets, targets: rows.targets, cost_sets, summary })
}

fn cost_chunk(
    model: &CostModel,
    fields: &NodeFields,
    rows: &Rows,
    chunk: &[u32],
    sets: &[SetStats],
) -> Result<ChunkCosts, CostGraphError> {
    let edges: usize = chunk.iter().map(|&i| rows.row(i as usize).len()).sum();
    let mut out = ChunkCosts {
        costs: vec![Vec::with_capacity(edges); model.set_count()],
        lengths: Vec::with_capacity(edges / STATS_STRIDE + 1),
        sets: sets.to_vec(),
    };
    let mut terms = EdgeTerms::default();
    for &i in chunk {
        let i = i as usize;
        for &j in rows.row(i) {
            model.edge(fields, i, j as usize, &mut terms);
            for (costs, &cost) in out.costs.iter_mut().zip(&terms.cost) {
                // Caught where it happens: the artifact's costs are f32, finite and > 0.
                let single = cost as f32;
                if !(single.is_finite() && single > 0.0) {
                    return Err(CostGraphError::CostOutOfRange { cost, length: terms.length });
                }
                costs.push(single);
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
