//! The network as every network format sees it: one record per skeleton node and one per
//! conduit segment, with the attributes of skeleton.json and hydro.json joined and the derived
//! ones computed once: node kind and degree, segment zone, Strahler order and branch id.
//!
//! - Node kind: `sink` and `spring` from hydro.json; otherwise from the node's degree in the
//!   simple graph (distinct neighbours): `junction` (≥ 3), `interior` (2), `dead_end` (≤ 1).
//! - Segment zone: `vadose` or `phreatic` when both ends are, `crossing` when the segment
//!   crosses the water table.
//! - Strahler order (Strahler 1957) on the wet segments directed downstream: a node with no wet
//!   inflow has order 1; otherwise the largest order of its inflows, plus one when two or more
//!   inflows share it; every outflow takes its node's order. Dry segments have order 0.
//! - Branch id: karstnet's branches (Collon et al. 2017), the chains of segments between nodes
//!   whose degree is not 2; ids from 1 in order of their first segment.

use glam::DVec3;

use karst_hydro::{Hydro, Role, WaterType};
use karst_skeleton::{ConduitType, Skeleton, Zone};

use crate::ExportError;

/// What a node is in the network.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum NodeKind {
    Sink,
    Spring,
    Junction,
    DeadEnd,
    Interior,
}

impl NodeKind {
    pub const ALL: [NodeKind; 5] =
        [NodeKind::Sink, NodeKind::Spring, NodeKind::Junction, NodeKind::DeadEnd, NodeKind::Interior];

    pub fn name(self) -> &'static str {
        match self {
            NodeKind::Sink => "sink",
            NodeKind::Spring => "spring",
            NodeKind::Junction => "junction",
            NodeKind::DeadEnd => "dead_end",
            NodeKind::Interior => "interior",
        }
    }
}

/// Where a segment lies relative to the water table.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum SegmentZone {
    Vadose,
    Phreatic,
    Crossing,
}

impl SegmentZone {
    pub const ALL: [SegmentZone; 3] = [SegmentZone::Vadose, SegmentZone::Phreatic, SegmentZone::Crossing];

    pub fn name(self) -> &'static str {
        match self {
            SegmentZone::Vadose => "vadose",
            SegmentZone::Phreatic => "phreatic",
            SegmentZone::Crossing => "crossing",
        }
    }
}

/// The code of `value` in a category list (its position), as numeric formats store it.
pub fn code<T: PartialEq>(all: &[T], value: T) -> i32 {
    all.iter().position(|v| *v == value).map_or(-1, |i| i as i32)
}

/// One node.
#[derive(Debug, Clone, PartialEq)]
pub struct NodeRecord {
    /// Local position, metres.
    pub position: [f64; 3],
    pub kind: NodeKind,
    pub zone: Zone,
    /// Largest radius of the conduits through the node, metres.
    pub radius: f64,
    /// Distinct neighbours.
    pub degree: u32,
    /// Hydraulic role and the water arriving, network units.
    pub role: Role,
    pub inflow: f64,
    /// The key point at the node.
    pub keypoint: Option<String>,
}

/// One segment `nodes[0] → nodes[1]` of a conduit (conduit order).
#[derive(Debug, Clone, PartialEq)]
pub struct SegmentRecord {
    /// 1-based segment id (conduit order, then segment order).
    pub id: u32,
    /// 1-based conduit id.
    pub conduit: u32,
    /// 0-based node indices, in conduit order.
    pub nodes: [u32; 2],
    /// Water flows `nodes[0] → nodes[1]` (false: the other way, or dry).
    pub downstream: bool,
    pub wet: bool,
    pub conduit_type: ConduitType,
    pub water: WaterType,
    pub zone: SegmentZone,
    pub phase: u32,
    /// Flow in network units and discharge in m³/s.
    pub flow: f64,
    pub discharge: f64,
    /// Water depth above the conduit floor, metres.
    pub depth: f64,
    /// Water surface at `nodes[0]` and `nodes[1]`, when known.
    pub level: Option<[f64; 2]>,
    /// Radius at `nodes[0]` and `nodes[1]`, metres (hydro's flow sizing when present).
    pub radius: [f64; 2],
    /// Half-height of the passage at `nodes[0]` and `nodes[1]`, metres: the radius times the
    /// passage profile's height-over-width factor there (the radius without a profile).
    pub half_height: [f64; 2],
    pub length: f64,
    pub strahler: u32,
    pub branch: u32,
}

impl SegmentRecord {
    /// The nodes in the direction water flows (conduit order when dry).
    pub fn flow_ends(&self) -> [u32; 2] {
        let [a, b] = self.nodes;
        if self.wet && !self.downstream { [b, a] } else { [a, b] }
    }

    /// A segment from a node to itself carries no length and no leg.
    pub fn is_loop(&self) -> bool {
        self.nodes[0] == self.nodes[1]
    }
}

/// A sink or spring: its node and name.
#[derive(Debug, Clone, PartialEq)]
pub struct Terminal {
    pub name: String,
    pub node: u32,
    /// Recharge (sinks) or discharge (springs), m³/s.
    pub discharge: f64,
}

/// The network with all its attributes.
#[derive(Debug, Clone, PartialEq)]
pub struct NetworkView {
    pub nodes: Vec<NodeRecord>,
    pub segments: Vec<SegmentRecord>,
    /// Conduits as ranges of `segments`.
    pub conduits: Vec<std::ops::Range<usize>>,
    pub sinks: Vec<Terminal>,
    pub springs: Vec<Terminal>,
}

impl NetworkView {
    /// Joins a skeleton and its hydro artifact, refusing a pair that does not belong together.
    pub fn new(skeleton: &Skeleton, hydro: &Hydro) -> Result<NetworkView, ExportError> {
        check_match(skeleton, hydro)?;
        let position = |n: u32| DVec3::from_array(skeleton.nodes[n as usize].position);
        let mut segments = Vec::new();
        let mut conduits = Vec::new();
        for (c, (conduit, water)) in skeleton.conduits.iter().zip(&hydro.conduits).enumerate() {
            let radii = water.radius.as_ref().unwrap_or(&conduit.radius);
            let at_nodes = conduit.node_profile_points(&skeleton.arc_lengths(conduit));
            let ratio = |i: usize| at_nodes.get(i).map_or(1.0, |&k| conduit.profile[k].ratio);
            let start = segments.len();
            for (i, (pair, s)) in conduit.nodes.windows(2).zip(&water.segments).enumerate() {
                let [a, b] = [pair[0], pair[1]];
                let zones = [a, b].map(|n| skeleton.nodes[n as usize].zone);
                segments.push(SegmentRecord {
                    id: segments.len() as u32 + 1,
                    conduit: c as u32 + 1,
                    nodes: [a, b],
                    downstream: s.downstream,
                    wet: s.flow > 0.0,
                    conduit_type: conduit.types[i],
                    water: s.water,
                    zone: match zones {
                        [Zone::Vadose, Zone::Vadose] => SegmentZone::Vadose,
                        [Zone::Phreatic, Zone::Phreatic] => SegmentZone::Phreatic,
                        _ => SegmentZone::Crossing,
                    },
                    phase: conduit.phase,
                    flow: s.flow,
                    discharge: s.discharge,
                    depth: s.depth,
                    level: s.level,
                    radius: [radii[i], radii[i + 1]],
                    half_height: [radii[i] * ratio(i), radii[i + 1] * ratio(i + 1)],
                    length: position(a).distance(position(b)),
                    strahler: 0,
                    branch: 0,
                });
            }
            conduits.push(start..segments.len());
        }
        let neighbours = neighbours(skeleton.nodes.len(), &segments);
        let terminal = |name: &str, node: u32, flow: f64| Terminal {
            name: name.to_string(),
            node,
            discharge: flow * discharge_per_flow(&segments),
        };
        let sinks: Vec<Terminal> =
            hydro.sinks.iter().map(|s| terminal(&s.name, s.node, s.recharge)).collect();
        let springs: Vec<Terminal> =
            hydro.springs.iter().map(|s| terminal(&s.name, s.node, s.flow)).collect();
        let mut radius = vec![0.0f64; skeleton.nodes.len()];
        for s in &segments {
            for (n, r) in s.nodes.iter().zip(s.radius) {
                radius[*n as usize] = radius[*n as usize].max(r);
            }
        }
        let nodes = skeleton
            .nodes
            .iter()
            .zip(&hydro.nodes)
            .enumerate()
            .map(|(i, (node, water))| {
                let degree = neighbours[i].len() as u32;
                let is = |list: &[Terminal]| list.iter().any(|t| t.node as usize == i);
                let kind = if is(&sinks) {
                    NodeKind::Sink
                } else if is(&springs) {
                    NodeKind::Spring
                } else {
                    match degree {
                        0 | 1 => NodeKind::DeadEnd,
                        2 => NodeKind::Interior,
                        _ => NodeKind::Junction,
                    }
                };
                NodeRecord {
                    position: node.position,
                    kind,
                    zone: node.zone,
                    radius: radius[i],
                    degree,
                    role: water.role,
                    inflow: water.inflow,
                    keypoint: node.keypoint.clone(),
                }
            })
            .collect();
        let mut view = NetworkView { nodes, segments, conduits, sinks, springs };
        view.set_strahler_orders();
        view.set_branches(&neighbours);
        Ok(view)
    }

    /// The connected part of every node: the smallest node index in it.
    pub fn parts(&self) -> Vec<usize> {
        let mut parent: Vec<usize> = (0..self.nodes.len()).collect();
        for s in &self.segments {
            union(&mut parent, s.nodes[0] as usize, s.nodes[1] as usize);
        }
        (0..self.nodes.len()).map(|n| find(&mut parent, n)).collect()
    }

    fn set_strahler_orders(&mut self) {
        let n = self.nodes.len();
        let mut incoming = vec![0usize; n];
        let mut outgoing: Vec<Vec<usize>> = vec![Vec::new(); n];
        for (k, s) in self.segments.iter().enumerate().filter(|(_, s)| s.wet && !s.is_loop()) {
            let [from, to] = s.flow_ends();
            incoming[to as usize] += 1;
            outgoing[from as usize].push(k);
        }
        let mut inflow_orders: Vec<Vec<u32>> = vec![Vec::new(); n];
        let mut ready: Vec<usize> = (0..n).filter(|&i| incoming[i] == 0).collect();
        while let Some(node) = ready.pop() {
            let orders = &inflow_orders[node];
            let top = orders.iter().copied().max().unwrap_or(1);
            let order = if orders.iter().filter(|&&o| o == top).count() >= 2 { top + 1 } else { top };
            for &k in &outgoing[node] {
                self.segments[k].strahler = order;
                let to = self.segments[k].flow_ends()[1] as usize;
                inflow_orders[to].push(order);
                incoming[to] -= 1;
                if incoming[to] == 0 {
                    ready.push(to);
                }
            }
        }
    }

    fn set_branches(&mut self, neighbours: &[Vec<u32>]) {
        let mut parent: Vec<usize> = (0..self.segments.len()).collect();
        let mut at_node: Vec<Option<usize>> = vec![None; self.nodes.len()];
        for (k, s) in self.segments.iter().enumerate() {
            for &n in &s.nodes {
                if neighbours[n as usize].len() != 2 {
                    continue;
                }
                match at_node[n as usize] {
                    Some(other) => union(&mut parent, k, other),
                    None => at_node[n as usize] = Some(k),
                }
            }
        }
        let mut ids = vec![0u32; self.segments.len()];
        let mut next = 0;
        for k in 0..self.segments.len() {
            let root = find(&mut parent, k);
            if ids[root] == 0 {
                next += 1;
                ids[root] = next;
            }
            self.segments[k].branch = ids[root];
        }
    }
}

fn find(parent: &mut [usize], mut k: usize) -> usize {
    while parent[k] != k {
        parent[k] = parent[parent[k]];
        k = parent[k];
    }
    k
}

fn union(parent: &mut [usize], a: usize, b: usize) {
    let (ra, rb) = (find(parent, a), find(parent, b));
    if ra != rb {
        parent[ra.max(rb)] = ra.min(rb);
    }
}

/// Distinct neighbours of every node, self-loops left out.
fn neighbours(n: usize, segments: &[SegmentRecord]) -> Vec<Vec<u32>> {
    let mut list: Vec<Vec<u32>> = vec![Vec::new(); n];
    for s in segments.iter().filter(|s| !s.is_loop()) {
        let [a, b] = s.nodes;
        list[a as usize].push(b);
        list[b as usize].push(a);
    }
    for l in &mut list {
        l.sort_unstable();
        l.dedup();
    }
    list
}

/// m³/s per network flow unit: hydro shares its total discharge in proportion to flow.
fn discharge_per_flow(segments: &[SegmentRecord]) -> f64 {
    segments.iter().find(|s| s.flow > 0.0).map_or(0.0, |s| s.discharge / s.flow)
}

fn check_match(skeleton: &Skeleton, hydro: &Hydro) -> Result<(), ExportError> {
    let mismatch = |what: &str, h: usize, s: usize| {
        Err(ExportError::Mismatch(format!("hydro.json describes {h} {what}, skeleton.json has {s}")))
    };
    if hydro.conduits.len() != skeleton.conduits.len() {
        return mismatch("conduits", hydro.conduits.len(), skeleton.conduits.len());
    }
    if hydro.nodes.len() != skeleton.nodes.len() {
        return mismatch("nodes", hydro.nodes.len(), skeleton.nodes.len());
    }
    for (c, (conduit, water)) in skeleton.conduits.iter().zip(&hydro.conduits).enumerate() {
        let segments = conduit.nodes.len().saturating_sub(1);
        let radii_ok = water.radius.as_ref().is_none_or(|r| r.len() == conduit.nodes.len());
        if water.segments.len() != segments || conduit.radius.len() != conduit.nodes.len() || !radii_ok {
            return mismatch(
                &format!("segments or radii in conduit {}", c + 1),
                water.segments.len(),
                segments,
            );
        }
        if conduit.nodes.iter().any(|&n| n as usize >= skeleton.nodes.len()) {
            return Err(ExportError::Mismatch(format!(
                "skeleton.json: conduit {} names a missing node",
                c + 1
            )));
        }
    }
    let terminals = hydro.sinks.iter().map(|s| s.node).chain(hydro.springs.iter().map(|s| s.node));
    if let Some(bad) = terminals.into_iter().find(|&n| n as usize >= skeleton.nodes.len()) {
        return Err(ExportError::Mismatch(format!("hydro.json names node {bad}, which skeleton.json lacks")));
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use karst_hydro::{ConduitWater, NodeWater, SegmentWater};
    use karst_skeleton::{Conduit, Node};

    use super::*;

    /// A Y: two sinks (0, 1) join at node 2, which drains to the spring 3 through node 4; a dry
    /// dead end 5 hangs off node 4.
    fn y_network() -> NetworkView {
        let node =
            |x: f64, z: f64| Node { position: [x, 0.0, z], sample: 0, keypoint: None, zone: Zone::Vadose };
        let nodes = vec![
            node(0.0, 30.0),
            node(10.0, 30.0),
            node(5.0, 20.0),
            node(5.0, 0.0),
            node(5.0, 10.0),
            node(8.0, 10.0),
        ];
        let conduit = |nodes: Vec<u32>| Conduit {
            radius: vec![1.0; nodes.len()],
            types: vec![ConduitType::Canyon; nodes.len() - 1],
            nodes,
            phase: 0,
            keypoints: Vec::new(),
            profile: Vec::new(),
        };
        let skeleton = Skeleton {
            nodes,
            conduits: vec![
                conduit(vec![0, 2]),
                conduit(vec![1, 2]),
                conduit(vec![2, 4, 3]),
                conduit(vec![5, 4]),
            ],
            routes: Vec::new(),
            derived: Default::default(),
        };
        let segment = |flow: f64| SegmentWater {
            downstream: true,
            flow,
            discharge: flow / 2.0,
            water: if flow > 0.0 { WaterType::Stream } else { WaterType::Dry },
            slope: 0.1,
            flow_units: 0.0,
            look: None,
            speed: 1.0,
            depth: 0.1,
            width: 0.5,
            level: None,
            fall: None,
        };
        let water = |flows: Vec<f64>| ConduitWater {
            flow: flows.iter().copied().fold(0.0, f64::max),
            downstream: true,
            dry: flows.iter().all(|f| *f == 0.0),
            radius: None,
            segments: flows.into_iter().map(segment).collect(),
        };
        let hydro_json = serde_json::json!({
            "flow_units": {"min": 1.0, "max": 2.0},
            "conduits": [],
            "nodes": [],
            "sinks": [{"name": "a", "node": 0, "recharge": 1.0, "springs": []}, {"name": "b", "node": 1, "recharge": 1.0, "springs": []}],
            "springs": [{"name": "s", "node": 3, "flow": 2.0, "sinks": []}],
        });
        let mut hydro: Hydro = serde_json::from_value(hydro_json).unwrap();
        hydro.conduits = vec![water(vec![1.0]), water(vec![1.0]), water(vec![2.0, 2.0]), water(vec![0.0])];
        hydro.nodes = (0..6).map(|_| NodeWater { role: Role::Branch, inflow: 0.0 }).collect();
        NetworkView::new(&skeleton, &hydro).unwrap()
    }

    #[test]
    fn kinds_orders_and_branches_of_a_y() {
        let net = y_network();
        let kinds: Vec<NodeKind> = net.nodes.iter().map(|n| n.kind).collect();
        use NodeKind::*;
        assert_eq!(kinds, [Sink, Sink, Junction, Spring, Junction, DeadEnd]);
        let orders: Vec<u32> = net.segments.iter().map(|s| s.strahler).collect();
        assert_eq!(orders, [1, 1, 2, 2, 0], "two order-1 streams make an order-2 one; dry is 0");
        let branches: Vec<u32> = net.segments.iter().map(|s| s.branch).collect();
        assert_eq!(branches, [1, 2, 3, 4, 5], "every node of the Y has a degree other than 2");
        assert_eq!(net.sinks[0].discharge, 0.5, "m³/s from the segments' discharge per flow");
        assert_eq!(net.parts(), vec![0; 6]);
    }

    #[test]
    fn artifacts_of_different_runs_are_refused() {
        let mut skeleton = Skeleton {
            nodes: Vec::new(),
            conduits: Vec::new(),
            routes: Vec::new(),
            derived: Default::default(),
        };
        skeleton.nodes.push(Node { position: [0.0; 3], sample: 0, keypoint: None, zone: Zone::Vadose });
        let hydro: Hydro = serde_json::from_value(serde_json::json!({
            "flow_units": {"min": 1.0, "max": 1.0}, "conduits": [], "nodes": [], "sinks": [], "springs": []
        }))
        .unwrap();
        let err = NetworkView::new(&skeleton, &hydro).unwrap_err().to_string();
        assert!(err.contains("hydro.json describes 0 nodes, skeleton.json has 1"), "{err}");
    }
}
