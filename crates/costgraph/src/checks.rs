//! What can be wrong with a cost graph before any path is searched: a key point with no
//! neighbour within the maximum edge length, and a sink that cannot reach a spring it must
//! connect to.
//!
//! Reachability does not depend on the costs (all are finite and > 0), so it is checked on the
//! bare graph: one traversal per spring on the reversed graph finds the nodes that can reach it,
//! which answers every sink at once; no path search per (sink, spring) pair. A traversal stops
//! as soon as it has found every sink (in a connected graph, long before it has visited every
//! sample), and the springs' traversals run in parallel: this check was a sequential 8 % of
//! the cost graph's time at 1M samples.

use rayon::prelude::*;

use karst_geology::{KeyPointKind, Link, Scene};
use karst_sampling::Samples;

use crate::CostGraphError;
use crate::knn::Rows;

/// A key point with no out-edge (no neighbour within `max_edge_length`).
pub fn isolated_keypoints(scene: &Scene, samples: &Samples, rows: &Rows) -> Result<(), CostGraphError> {
    for (i, keypoint) in scene.keypoints().iter().enumerate() {
        let Some(sample) = samples.keypoint_sample(i) else { continue };
        if rows.row(sample).is_empty() {
            return Err(CostGraphError::IsolatedKeyPoint {
                name: keypoint.name.clone(),
                max_edge_length: scene.costgraph().max_edge_length.unwrap_or(f64::INFINITY),
            });
        }
    }
    Ok(())
}

/// Every sink reaches each spring its connectivity row marks 1, and, when the row has no 1,
/// at least one of the springs it marks 2.
pub fn sinks_reach_their_springs(
    scene: &Scene,
    samples: &Samples,
    rows: &Rows,
) -> Result<(), CostGraphError> {
    let springs: Vec<(&str, Option<usize>)> = scene
        .keypoints_of(KeyPointKind::Spring)
        .map(|(i, k)| (k.name.as_str(), samples.keypoint_sample(i)))
        .collect();
    let sinks: Vec<(&str, Option<usize>)> = scene
        .keypoints_of(KeyPointKind::Sink)
        .map(|(i, k)| (k.name.as_str(), samples.keypoint_sample(i)))
        .collect();
    let reverse = rows.transpose();
    let sink_samples: Vec<usize> = sinks.iter().filter_map(|(_, sample)| *sample).collect();
    let reaching: Vec<Option<Vec<bool>>> = springs
        .par_iter()
        .map(|(_, sample)| sample.map(|s| reached_from(&reverse, s, &sink_samples)))
        .collect();
    for (row, (sink, sink_sample)) in sinks.iter().enumerate() {
        let Some(sink_sample) = *sink_sample else { continue };
        let reaches = |col: usize| reaching[col].as_ref().is_none_or(|r| r[sink_sample]);
        let links: Vec<Link> = (0..springs.len()).map(|col| scene.link(row, col)).collect();
        if links.contains(&Link::Connected) {
            if let Some(col) = (0..springs.len()).find(|&c| links[c] == Link::Connected && !reaches(c)) {
                return Err(unreachable(scene, sink, &[springs[col].0]));
            }
        } else {
            let candidates: Vec<usize> =
                (0..springs.len()).filter(|&c| links[c] == Link::Uncertain).collect();
            if !candidates.is_empty() && !candidates.iter().any(|&c| reaches(c)) {
                let names: Vec<&str> = candidates.iter().map(|&c| springs[c].0).collect();
                return Err(unreachable(scene, sink, &names));
            }
        }
    }
    Ok(())
}

fn unreachable(scene: &Scene, sink: &str, springs: &[&str]) -> CostGraphError {
    CostGraphError::Unreachable {
        sink: sink.to_string(),
        springs: springs.iter().map(|s| format!("\"{s}\"")).collect::<Vec<_>>().join(" or "),
        k: scene.costgraph().k,
        max_edge_length: scene.costgraph().max_edge_length.unwrap_or(f64::INFINITY),
    }
}

/// Nodes reached from `start` along the edges of `rows`, marked until every node of `wanted` is
/// (then the traversal stops: other nodes may be left unmarked, the nodes of `wanted` are
/// marked exactly when they are reached).
fn reached_from(rows: &Rows, start: usize, wanted: &[usize]) -> Vec<bool> {
    let mut is_wanted = vec![false; rows.node_count()];
    for &w in wanted {
        is_wanted[w] = true;
    }
    let mut missing = is_wanted.iter().filter(|&&w| w).count();
    let mut seen = vec![false; rows.node_count()];
    let mut queue = vec![start];
    let mut mark = |v: usize, seen: &mut [bool]| {
        seen[v] = true;
        if is_wanted[v] {
            missing -= 1;
        }
        missing == 0
    };
    if mark(start, &mut seen) {
        return seen;
    }
    while let Some(u) = queue.pop() {
        for &v in rows.row(u) {
            let v = v as usize;
            if !seen[v] {
                if mark(v, &mut seen) {
                    return seen;
                }
                queue.push(v);
            }
        }
    }
    seen
}

#[cfg(test)]
mod tests {
    use super::*;

    /// 0 → 1 → 2 → 3, 4 → 0, and 5 alone.
    fn chain() -> Rows {
        Rows { offsets: vec![0, 1, 2, 3, 3, 4, 4], targets: vec![1, 2, 3, 0] }
    }

    #[test]
    fn the_traversal_marks_the_wanted_nodes_it_reaches() {
        let rows = chain();
        let all: Vec<usize> = (0..6).collect();
        assert_eq!(reached_from(&rows, 0, &all), vec![true, true, true, true, false, false]);
        for wanted in [vec![1], vec![3, 5], vec![4, 2], vec![5], vec![0], vec![]] {
            let seen = reached_from(&rows, 0, &wanted);
            for w in wanted {
                assert_eq!(seen[w], w <= 3, "node {w}");
            }
        }
        // It stops once the wanted nodes are found: 3 is not visited when only 1 is wanted.
        assert!(!reached_from(&rows, 0, &[1])[3]);
    }
}
