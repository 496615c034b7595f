//! Routing every sink to its spring(s) and merging the routes into one network.
//!
//! Sinks are routed in their `order` (then scene order). A sink drains to every spring its
//! connectivity row marks 1; when the row has no 1, to the cheapest of the springs marked 2
//! (KarstNSim §1.4: uncertain connectivity keeps the closest spring in the cost metric).
//! Routes that pass through the same sample share its node, which is how branches join.

use std::collections::{HashMap, HashSet};

use karst_artifact::StageError;
use karst_costgraph::CostGraph;
use karst_geology::rng::Random;
use karst_geology::{KeyPointKind, Link, Scene};
use karst_sampling::Samples;

use crate::classify::classify;
use crate::dijkstra::ShortestPaths;
use crate::{Conduit, Node, Route, Skeleton, Zone};

/// A key point of the routing problem: its index among sinks or springs, its scene key point.
struct End<'a> {
    row: usize,
    keypoint: usize,
    name: &'a str,
}

/// Builds the network of `scene` on the cost graph.
pub fn build(scene: &Scene, samples: &Samples, graph: &CostGraph) -> Result<Skeleton, StageError> {
    let routes = route_sinks(scene, samples, graph)?;
    let mut network = NetworkBuilder::default();
    for route in &routes {
        network.add_path(&route.1);
    }
    let routes: Vec<Route> =
        routes.into_iter().map(|(r, path)| Route { nodes: network.ids(&path), ..r }).collect();
    let chains = network.conduit_chains(scene, samples);
    let mut rng = Random::stream(scene.seed, "skeleton", "radius");
    let [lo, hi] = scene.skeleton.radius;
    let nodes: Vec<Node> = network.samples.iter().map(|&s| node(scene, samples, s)).collect();
    let at = |i: u32| karst_geology::Point::from_array(nodes[i as usize].position);
    let conduits = chains
        .into_iter()
        .map(|chain| {
            let r = rng.range(lo, hi);
            let types = chain.windows(2).map(|w| classify(scene, at(w[0]), at(w[1]))).collect();
            Conduit { radius: vec![r; chain.len()], nodes: chain, types }
        })
        .collect();
    Ok(Skeleton { nodes, conduits, routes })
}

fn node(scene: &Scene, samples: &Samples, sample: u32) -> Node {
    let position = samples.positions[sample as usize];
    let p = karst_geology::Point::from_array(position);
    let phreatic = scene.geology.water_tables.iter().any(|w| w.height_above(p) < 0.0);
    let keypoint =
        scene.keypoints.get(sample as usize).filter(|_| samples.keypoint_sample(sample as usize).is_some());
    Node {
        position,
        sample,
        keypoint: keypoint.map(|k| k.name.clone()),
        zone: if phreatic { Zone::Phreatic } else { Zone::Vadose },
    }
}

/// Routes of every sink, with the sample path of each.
fn route_sinks(
    scene: &Scene,
    samples: &Samples,
    graph: &CostGraph,
) -> Result<Vec<(Route, Vec<usize>)>, StageError> {
    let ends = |kind| -> Vec<End> {
        scene
            .keypoints_of(kind)
            .enumerate()
            .map(|(row, (keypoint, k))| End { row, keypoint, name: &k.name })
            .collect()
    };
    let mut sinks = ends(KeyPointKind::Sink);
    let springs = ends(KeyPointKind::Spring);
    sinks.sort_by_key(|s| (scene.keypoints[s.keypoint].order, s.row));
    let mut routes = Vec::new();
    for sink in &sinks {
        let source = sample_of(samples, sink)?;
        let candidates: Vec<(&End, Link)> = springs
            .iter()
            .map(|t| (t, scene.link(sink.row, t.row)))
            .filter(|(_, l)| *l != Link::None)
            .collect();
        let targets = candidates.iter().map(|(t, _)| sample_of(samples, t)).collect::<Result<Vec<_>, _>>()?;
        // One search per spring, in the cost set of its water table (KarstNSim §1.3).
        let set = |t: &End| {
            scene.keypoints[t.keypoint].water_table.as_deref().and_then(|w| graph.cost_set_of_water_table(w))
        };
        let paths: Vec<ShortestPaths> = candidates
            .iter()
            .zip(&targets)
            .map(|((t, _), &target)| ShortestPaths::from(graph, set(t).unwrap_or(0), source, &[target]))
            .collect();
        let unreachable = |t: &End| {
            StageError::input(format!(
                "sink \"{}\" cannot reach spring \"{}\" through the cost graph (raise costgraph.k or max_edge_length)",
                sink.name, t.name
            ))
        };
        let chosen: Vec<&End> = if candidates.iter().any(|(_, l)| *l == Link::Connected) {
            candidates.iter().filter(|(_, l)| *l == Link::Connected).map(|(t, _)| *t).collect()
        } else {
            let cheapest = candidates
                .iter()
                .zip(targets.iter().zip(&paths))
                .min_by(|a, b| a.1.1.cost(*a.1.0).total_cmp(&b.1.1.cost(*b.1.0)))
                .map(|((t, _), _)| *t);
            cheapest.into_iter().collect()
        };
        for spring in chosen {
            let target = sample_of(samples, spring)?;
            let paths = &paths[candidates
                .iter()
                .position(|(t, _)| std::ptr::eq(*t, spring))
                .expect("a chosen spring is a candidate")];
            let path = paths.path(target).ok_or_else(|| unreachable(spring))?;
            let k = &scene.keypoints[sink.keypoint];
            let route = Route {
                sink: sink.name.to_string(),
                spring: spring.name.to_string(),
                weight: k.weight,
                nodes: Vec::new(),
                cost: paths.cost(target),
            };
            routes.push((route, path));
        }
    }
    Ok(routes)
}

fn sample_of(samples: &Samples, end: &End) -> Result<usize, StageError> {
    samples.keypoint_sample(end.keypoint).ok_or_else(|| {
        StageError::input(format!(
            "key point \"{}\" is not in samples.bin (the scene changed since sampling: rerun `cargo xtask run --from sampling`)",
            end.name
        ))
    })
}

/// The network as it grows: nodes in order of first appearance, undirected links.
#[derive(Default)]
struct NetworkBuilder {
    samples: Vec<u32>,
    id_of: HashMap<u32, u32>,
    adjacency: Vec<Vec<u32>>,
}

impl NetworkBuilder {
    fn id(&mut self, sample: usize) -> u32 {
        let next = self.samples.len() as u32;
        *self.id_of.entry(sample as u32).or_insert_with(|| {
            self.samples.push(sample as u32);
            self.adjacency.push(Vec::new());
            next
        })
    }

    fn ids(&self, path: &[usize]) -> Vec<u32> {
        path.iter().map(|s| self.id_of[&(*s as u32)]).collect()
    }

    fn add_path(&mut self, path: &[usize]) {
        let ids: Vec<u32> = path.iter().map(|&s| self.id(s)).collect();
        for w in ids.windows(2) {
            let (a, b) = (w[0], w[1]);
            if a != b && !self.adjacency[a as usize].contains(&b) {
                self.adjacency[a as usize].push(b);
                self.adjacency[b as usize].push(a);
            }
        }
    }

    /// Cuts the network into chains between ends: nodes of degree ≠ 2 and key points.
    /// Isolated cycles become one closed chain each.
    fn conduit_chains(&mut self, scene: &Scene, samples: &Samples) -> Vec<Vec<u32>> {
        for list in &mut self.adjacency {
            list.sort_unstable();
        }
        let is_end: Vec<bool> = (0..self.samples.len())
            .map(|i| {
                let s = self.samples[i] as usize;
                self.adjacency[i].len() != 2
                    || (s < scene.keypoints.len() && samples.keypoint_sample(s).is_some())
            })
            .collect();
        let mut used = HashSet::new();
        let mut chains = Vec::new();
        let starts: Vec<u32> = (0..self.samples.len() as u32).filter(|&i| is_end[i as usize]).collect();
        let cycle_starts = 0..self.samples.len() as u32;
        for start in starts.into_iter().chain(cycle_starts) {
            for &next in &self.adjacency[start as usize].clone() {
                if used.contains(&(start.min(next), start.max(next))) {
                    continue;
                }
                chains.push(self.walk(start, next, &is_end, &mut used));
            }
        }
        chains
    }

    fn walk(&self, start: u32, first: u32, is_end: &[bool], used: &mut HashSet<(u32, u32)>) -> Vec<u32> {
        let mut chain = vec![start];
        let (mut prev, mut at) = (start, first);
        loop {
            used.insert((prev.min(at), prev.max(at)));
            chain.push(at);
            if is_end[at as usize] || at == start {
                return chain;
            }
            let next =
                self.adjacency[at as usize].iter().copied().find(|&n| n != prev).expect("degree-2 node");
            (prev, at) = (at, next);
        }
    }
}
