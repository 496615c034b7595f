//! What can be wrong with a cost graph before any path is searched: a key point with no
//! neighbour within the maximum edge length, and a sink that cannot reach a spring it must
//! connect to.
//!
//! Reachability does not depend on the costs (all are finite and > 0), so it is checked on the
//! bare graph: one breadth-first search per spring on the reversed graph finds every node that
//! can reach it, which answers every sink at once; no path search per (sink, spring) pair.

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
    let reaching: Vec<Option<Vec<bool>>> =
        springs.iter().map(|(_, sample)| sample.map(|s| reached_from(&reverse, s))).collect();
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

/// Nodes reached from `start` along the edges of `rows`.
fn reached_from(rows: &Rows, start: usize) -> Vec<bool> {
    let mut seen = vec![false; rows.node_count()];
    let mut queue = vec![start];
    seen[start] = true;
    while let Some(u) = queue.pop() {
        for &v in rows.row(u) {
            if !seen[v as usize] {
                seen[v as usize] = true;
                queue.push(v as usize);
            }
        }
    }
    seen
}
