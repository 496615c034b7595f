//! What can be wrong with a cost graph before any path is searched: a sample tagged with a
//! surface or key point the scene does not have, a key point with no neighbour within the
//! maximum edge length, and a sink that cannot reach a spring it must connect to.
//!
//! Reachability does not depend on the costs (all are finite and > 0), so it is checked on the
//! bare graph, forwards from each sink, by a best-first traversal that always extends the
//! reached sample nearest to the spring. The graph joins each sample to its nearest
//! neighbours, so the traversal runs nearly straight to the spring and visits a few thousand
//! samples, whatever the graph's size; around an obstacle (a no-karst volume, a valley) it
//! fills the pocket and goes on, and it visits everything the sink reaches only when the
//! spring is out of reach, the case it reports. The earlier check, one traversal per spring
//! of the reversed graph, needed that reversed graph: 8 bytes per edge, and a share of the
//! network half's instructions (BENCHMARKS.md).

use std::cmp::Reverse;
use std::collections::BinaryHeap;

use rayon::prelude::*;

use karst_sampling::{Samples, Tag};
use karst_scene::params::CostgraphParams;
use karst_scene::{KeyPointKind, Link, keypoints_of};

use crate::CostGraphError;
use crate::knn::Rows;
use crate::view::CostgraphView;

/// The first sample whose tag names a horizon, water table, fault or key point beyond the
/// scene's: samples.bin was made from another scene (or damaged), and the searches would
/// read a surface that is not there.
pub fn tags_of_the_scene(view: &CostgraphView, samples: &Samples) -> Result<(), CostGraphError> {
    let geology = view.geology;
    for (index, tag) in samples.tags.iter().enumerate() {
        let (kind, i, count) = match *tag {
            Tag::Volume => continue,
            Tag::Horizon(i) => ("horizon", i, geology.horizons.len()),
            Tag::WaterTable(i) => ("water table", i, geology.water_tables.len()),
            Tag::Fault(i) => ("fault", i, geology.faults.len()),
            Tag::KeyPoint(i) => ("key point", i, view.keypoints.len()),
        };
        if i as usize >= count {
            return Err(CostGraphError::ForeignTag { index, tag: format!("{kind} {i}"), count });
        }
    }
    Ok(())
}

/// A key point with no out-edge (no neighbour within `max_edge_length`).
pub fn isolated_keypoints(
    view: &CostgraphView,
    samples: &Samples,
    rows: &Rows,
) -> Result<(), CostGraphError> {
    for (i, keypoint) in view.keypoints.iter().enumerate() {
        let Some(sample) = samples.keypoint_sample(i) else { continue };
        if rows.row(sample).is_empty() {
            return Err(CostGraphError::IsolatedKeyPoint {
                name: keypoint.name.clone(),
                max_edge_length: view.costgraph.max_edge_length.unwrap_or(f64::INFINITY),
            });
        }
    }
    Ok(())
}

/// Every sink reaches each spring its connectivity row marks 1, and, when the row has no 1,
/// at least one of the springs it marks 2. The sinks are checked in parallel.
pub fn sinks_reach_their_springs(
    view: &CostgraphView,
    samples: &Samples,
    rows: &Rows,
) -> Result<(), CostGraphError> {
    let springs: Vec<(&str, Option<usize>)> = keypoints_of(view.keypoints, KeyPointKind::Spring)
        .map(|(i, k)| (k.name.as_str(), samples.keypoint_sample(i)))
        .collect();
    let sinks: Vec<(usize, &str, usize)> = keypoints_of(view.keypoints, KeyPointKind::Sink)
        .enumerate()
        .filter_map(|(row, (i, k))| Some((row, k.name.as_str(), samples.keypoint_sample(i)?)))
        .collect();
    let failures: Vec<Option<CostGraphError>> = sinks
        .par_iter()
        .map(|&(row, sink, sink_sample)| {
            // A spring without a sample of its own is not checked (as if reached).
            let reaches =
                |col: usize| springs[col].1.is_none_or(|s| reaches(rows, &samples.positions, sink_sample, s));
            let links: Vec<Link> = (0..springs.len()).map(|col| view.connectivity.link(row, col)).collect();
            if links.contains(&Link::Connected) {
                let missing = (0..springs.len()).find(|&c| links[c] == Link::Connected && !reaches(c));
                missing.map(|col| unreachable(view.costgraph, sink, &[springs[col].0]))
            } else {
                let candidates: Vec<usize> =
                    (0..springs.len()).filter(|&c| links[c] == Link::Uncertain).collect();
                let none = !candidates.is_empty() && !candidates.iter().any(|&c| reaches(c));
                let names: Vec<&str> = candidates.iter().map(|&c| springs[c].0).collect();
                none.then(|| unreachable(view.costgraph, sink, &names))
            }
        })
        .collect();
    // The first sink in the scene's order that fails, whatever the thread count.
    failures.into_iter().flatten().next().map_or(Ok(()), Err)
}

fn unreachable(p: &CostgraphParams, sink: &str, springs: &[&str]) -> CostGraphError {
    CostGraphError::Unreachable {
        sink: sink.to_string(),
        springs: springs.iter().map(|s| format!("\"{s}\"")).collect::<Vec<_>>().join(" or "),
        k: p.k,
        max_edge_length: p.max_edge_length.unwrap_or(f64::INFINITY),
    }
}

/// Whether `to` can be reached from `from` along the edges of `rows`: a best-first traversal
/// (`positions`: the nodes') that extends the reached node nearest to `to` first, and stops
/// when it reaches `to` or has visited everything `from` reaches.
fn reaches(rows: &Rows, positions: &[[f64; 3]], from: usize, to: usize) -> bool {
    // Squared distances are ≥ 0: their bits order as they do.
    let nearness = |v: usize| crate::grid::distance2(&positions[v], &positions[to]).to_bits();
    let mut seen = vec![false; rows.node_count()];
    let mut frontier = BinaryHeap::from([Reverse((nearness(from), from as u32))]);
    seen[from] = true;
    while let Some(Reverse((_, u))) = frontier.pop() {
        if u as usize == to {
            return true;
        }
        for &v in rows.row(u as usize) {
            if !std::mem::replace(&mut seen[v as usize], true) {
                frontier.push(Reverse((nearness(v as usize), v)));
            }
        }
    }
    false
}

#[cfg(test)]
mod tests {
    use super::*;

    /// 0 → 1 → 2 → 3, 4 → 0, and 5 alone, on a line (node i at x = i), with a detour: 0 → 6,
    /// a dead end nearer to 3 than 0 is.
    fn chain() -> (Rows, Vec<[f64; 3]>) {
        let rows = Rows { offsets: vec![0, 2, 3, 4, 4, 5, 5, 5], targets: vec![6, 1, 2, 3, 0] };
        let mut positions: Vec<[f64; 3]> = (0..6).map(|i| [i as f64, 0.0, 0.0]).collect();
        positions.push([2.5, 0.1, 0.0]);
        (rows, positions)
    }

    #[test]
    fn a_node_is_reached_exactly_when_a_path_leads_to_it() {
        let (rows, positions) = chain();
        for from in 0..7 {
            for to in 0..7 {
                let path = match from {
                    0 => to <= 3 || to == 6,
                    4 => to <= 4 || to == 6,
                    1..=3 => from <= to && to <= 3,
                    _ => from == to,
                };
                assert_eq!(reaches(&rows, &positions, from, to), path, "{from} → {to}");
            }
        }
    }
}
