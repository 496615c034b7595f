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
    for (i, keypoint) in scene.keypoints.iter().enumerate() {
        let Some(sample) = samples.keypoint_sample(i) else { continue };
        if rows.row(sample).is_empty() {
            return Err(CostGraphError::IsolatedKeyPoint {
                name: keypoint.name.clone(),
                max_edge_length: scene.costgraph.max_edge_length.unwrap_or(f64::INFINITY),
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
    // Usually every key point lies in one strongly connected component: then every sink reaches
    // every spring, known after one depth-first pass and without the reversed graph.
    let keypoints: Vec<usize> = springs.iter().chain(&sinks).filter_map(|(_, s)| *s).collect();
    if let Some((&first, rest)) = keypoints.split_first() {
        let component = component_of(rows, first);
        if rest.iter().all(|&k| component[k]) {
            return Ok(());
        }
    }
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
        k: scene.costgraph.k,
        max_edge_length: scene.costgraph.max_edge_length.unwrap_or(f64::INFINITY),
    }
}

/// The strongly connected component of `root`: the nodes that both reach it and are reached
/// from it (Tarjan's algorithm from `root`, iterative, over the nodes `root` reaches).
fn component_of(rows: &Rows, root: usize) -> Vec<bool> {
    let mut search = Tarjan::new(rows.node_count());
    search.visit(rows, root);
    let mut component = vec![false; rows.node_count()];
    while let Some(&(v, next)) = search.path.last() {
        let v = v as usize;
        if next < rows.offsets[v + 1] {
            search.path.last_mut().expect("non-empty").1 += 1;
            let w = rows.targets[next as usize] as usize;
            if search.index[w] == UNSEEN {
                search.visit(rows, w);
            } else if search.on_stack[w] {
                search.low[v] = search.low[v].min(search.index[w]);
            }
            continue;
        }
        search.path.pop();
        if let Some(&(parent, _)) = search.path.last() {
            search.low[parent as usize] = search.low[parent as usize].min(search.low[v]);
        }
        if search.low[v] == search.index[v] {
            // v roots a component: the nodes above it on the stack.
            loop {
                let w = search.stack.pop().expect("v is on the stack") as usize;
                search.on_stack[w] = false;
                component[w] = v == root;
                if w == v {
                    break;
                }
            }
        }
    }
    component
}

const UNSEEN: u32 = u32::MAX;

/// The state of Tarjan's depth-first search.
struct Tarjan {
    index: Vec<u32>,
    low: Vec<u32>,
    on_stack: Vec<bool>,
    stack: Vec<u32>,
    /// The depth-first path: each node with the position of its next edge.
    path: Vec<(u32, u32)>,
    count: u32,
}

impl Tarjan {
    fn new(n: usize) -> Self {
        Tarjan {
            index: vec![UNSEEN; n],
            low: vec![0; n],
            on_stack: vec![false; n],
            stack: Vec::new(),
            path: Vec::new(),
            count: 0,
        }
    }

    fn visit(&mut self, rows: &Rows, v: usize) {
        (self.index[v], self.low[v]) = (self.count, self.count);
        self.count += 1;
        self.stack.push(v as u32);
        self.on_stack[v] = true;
        self.path.push((v as u32, rows.offsets[v]));
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

#[cfg(test)]
mod tests {
    use super::*;

    fn rows(lists: &[&[u32]]) -> Rows {
        let mut offsets = vec![0];
        let mut targets = Vec::new();
        for list in lists {
            targets.extend_from_slice(list);
            offsets.push(targets.len() as u32);
        }
        Rows { offsets, targets }
    }

    #[test]
    fn the_component_of_a_node_is_what_both_reaches_it_and_is_reached() {
        // 0 ⇄ 1 → 2 ⇄ 3, 3 → 0 closes a cycle over all four; 4 only reaches in, 5 only out.
        let g = rows(&[&[1], &[0, 2], &[3], &[2, 0, 5], &[0], &[]]);
        assert_eq!(component_of(&g, 0), [true, true, true, true, false, false]);
        // Without 3 → 0: {0, 1} and {2, 3} are separate components.
        let g = rows(&[&[1], &[0, 2], &[3], &[2, 5], &[0], &[]]);
        assert_eq!(component_of(&g, 0), [true, true, false, false, false, false]);
        assert_eq!(component_of(&g, 3), [false, false, true, true, false, false]);
        assert_eq!(component_of(&g, 5), [false, false, false, false, false, true]);
        for root in 0..6 {
            let c = component_of(&g, root);
            let forward = reached_from(&g, root);
            let backward = reached_from(&g.transpose(), root);
            for v in 0..6 {
                assert_eq!(c[v], forward[v] && backward[v], "root {root}, node {v}");
            }
        }
    }
}
