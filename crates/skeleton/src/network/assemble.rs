//! From sample paths to the skeleton artifact: paths that pass through the same sample share
//! its node (which is how branches join), the network is cut into conduits between ends
//! (junctions, dead ends and key points), and every segment gets its tunnel type.

use std::collections::{HashMap, HashSet};

use karst_geology::Point;
use karst_sampling::Samples;

use crate::network::classify::classify;
use crate::network::nodes::{is_keypoint, node};
use crate::network::shape::passages::{self, ConduitPassage, PassageProfiles};
use crate::network::shape::radii::ConduitRadii;
use crate::network::shape::{meander, tortuosity};
use crate::payload::{Conduit, Node, Route, Skeleton};
use crate::view::SkeletonView;

/// The network as it grows: nodes in order of first appearance, undirected links.
#[derive(Default)]
pub struct NetworkBuilder {
    /// Sample of each node.
    pub samples: Vec<u32>,
    id_of: HashMap<u32, u32>,
    /// Neighbours of each node, in insertion order.
    pub adjacency: Vec<Vec<u32>>,
    /// The phase paths are added in.
    pub phase: u32,
    /// The phase that made each link (a < b).
    link_phase: HashMap<(u32, u32), u32>,
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

    /// Node ids of a path of samples already added.
    pub fn ids(&self, path: &[usize]) -> Vec<u32> {
        path.iter().map(|s| self.id_of[&(*s as u32)]).collect()
    }

    /// Node of `sample`, if the network passes through it.
    pub fn node_of(&self, sample: usize) -> Option<u32> {
        self.id_of.get(&(sample as u32)).copied()
    }

    /// Adds a path of samples (consecutive samples become a link).
    pub fn add_path(&mut self, path: &[usize]) {
        let ids: Vec<u32> = path.iter().map(|&s| self.id(s)).collect();
        for w in ids.windows(2) {
            let (a, b) = (w[0], w[1]);
            if a != b && !self.adjacency[a as usize].contains(&b) {
                self.adjacency[a as usize].push(b);
                self.adjacency[b as usize].push(a);
                self.link_phase.insert((a.min(b), a.max(b)), self.phase);
            }
        }
    }

    /// The skeleton: nodes, conduits with types and radii, and `routes` (sample paths turned
    /// into node paths).
    pub fn finish(
        mut self,
        view: &SkeletonView,
        samples: &Samples,
        routes: Vec<(Route, Vec<usize>)>,
    ) -> Skeleton {
        let mut routes: Vec<Route> =
            routes.into_iter().map(|(r, path)| Route { nodes: self.ids(&path), ..r }).collect();
        let mut chains = self.conduit_chains(samples);
        let phases: Vec<u32> = chains.iter().map(|c| self.phase_of(c[0], c[1])).collect();
        let mut nodes: Vec<Node> = self.samples.iter().map(|&s| node(view, samples, s)).collect();
        if let Some(theta) = view.skeleton.tortuosity {
            let inserted = tortuosity::refine(view, theta, &mut nodes, &mut chains);
            tortuosity::reroute(&mut routes, &inserted);
        }
        let sinuosity = view.skeleton.sinuosity;
        if sinuosity > 1.0 {
            let inserted = meander::bend(view, sinuosity, &mut nodes, &mut chains);
            tortuosity::reroute(&mut routes, &inserted);
        }
        let mut radii = ConduitRadii::new(view.skeleton, view.seed, nodes.len());
        let mut passages = view.passage_detail.varies().then(|| PassageProfiles::new(view.seed, nodes.len()));
        let junction = passages::junctions(&chains, nodes.len());
        let flow = passages::flow_factors(&chains, &routes, &nodes);
        let at = |i: u32| Point::from_array(nodes[i as usize].position);
        let conduits = chains
            .into_iter()
            .zip(phases)
            .zip(flow)
            .map(|((chain, phase), flow)| {
                let types: Vec<_> = chain.windows(2).map(|w| classify(view, at(w[0]), at(w[1]))).collect();
                let ends = [chain[0], chain[chain.len() - 1]];
                let keypoints = ends.iter().filter_map(|&i| nodes[i as usize].keypoint.clone()).collect();
                let mut radius = radii.conduit(&nodes, &chain, &types);
                let profile = match passages.as_mut() {
                    Some(passages) => {
                        let junction = chain.iter().map(|&n| junction[n as usize]).collect();
                        let passage = ConduitPassage {
                            nodes: &nodes,
                            chain: &chain,
                            types: &types,
                            radius: &radius,
                            junction,
                            flow,
                        };
                        let (profile, at_nodes) = passages.conduit(&passage);
                        radius = at_nodes;
                        profile
                    }
                    None => Vec::new(),
                };
                Conduit { radius, nodes: chain, types, phase, keypoints, profile }
            })
            .collect();
        Skeleton { nodes, conduits, routes, derived: Default::default() }
    }

    fn phase_of(&self, a: u32, b: u32) -> u32 {
        self.link_phase[&(a.min(b), a.max(b))]
    }

    /// Cuts the network into chains between ends: nodes of degree ≠ 2, key points and nodes
    /// where the phase changes. Isolated cycles become one closed chain each.
    fn conduit_chains(&mut self, samples: &Samples) -> Vec<Vec<u32>> {
        for list in &mut self.adjacency {
            list.sort_unstable();
        }
        let is_end: Vec<bool> = (0..self.samples.len())
            .map(|i| {
                let next = &self.adjacency[i];
                let phase_changes =
                    next.len() == 2 && self.phase_of(i as u32, next[0]) != self.phase_of(i as u32, next[1]);
                next.len() != 2 || phase_changes || is_keypoint(samples, self.samples[i])
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
