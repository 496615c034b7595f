//! The SWMM model of a network, as numbers: nodes (junctions, storage units, outfalls) with
//! their inverts and depths, conduits with their ends, offsets, lengths, sections and hydro's
//! discharge, and the sinks' inflows. swmm.rs writes it; steady.rs finds its steady state. All
//! elevations and lengths are rounded as they are written (4 decimals), so that the steady
//! state is computed on exactly the model SWMM reads.
//!
//! - Junctions at the network nodes the merged conduits end at, named by their 1-based node id; invert = the lowest
//!   conduit floor at the node, full depth up to the highest conduit crown there, surcharge
//!   depth up to the highest crown of the network (closed rock: phreatic conduits may be
//!   pressurized that far).
//! - Pools (hydro's ponds and chamber nodes) that stay nodes of the model (chains.rs merges
//!   plain passage nodes, pools included: a flooded pool is its conduits' volume) are storage
//!   units with the horizontal area of their widest conduit.
//! - Conduits are the segments merged into runs of at least `export.swmm_conduit_length`
//!   (chains.rs), named by the 1-based id of their segment (`FIRST-LAST` for several),
//!   pointing downstream (conduit order when dry), their centreline through the nodes (offsets
//!   above the node invert). Segments steeper than `export.swmm_max_slope` (shafts) keep that slope and drop
//!   the rest at their lower end, as drop structures are modelled in SWMM.
//! - Each spring is a junction drained by a short conduit `SPRING_outlet` to a free outfall
//!   `SPRING` (an outfall may have one link only, and a spring may have several conduits).

use std::collections::BTreeMap;
use std::f64::consts::PI;

use karst_hydro::Role;
use karst_skeleton::ConduitType;

use karst_scene::params::ExportParams;

use super::chains::{self, Reach};
use super::section::Section;
use crate::frame::Frame;
use crate::network::NetworkView;

/// What a node of the model is.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum NodeKind {
    Junction,
    /// A storage unit of constant horizontal area, m².
    Storage(f64),
    Outfall,
}

/// One node: name, kind, invert elevation, full depth and surcharge depth (metres), map
/// position.
#[derive(Debug, Clone, PartialEq)]
pub struct Node {
    pub name: String,
    pub kind: NodeKind,
    pub invert: f64,
    pub depth: f64,
    pub surcharge: f64,
    pub xy: [f64; 2],
}

/// One conduit from `ends[0]` to `ends[1]` (model node indices, along the water).
#[derive(Debug, Clone, PartialEq)]
pub struct Conduit {
    pub name: String,
    pub ends: [usize; 2],
    /// Height of the conduit's floor above each end node's invert, metres.
    pub offsets: [f64; 2],
    pub length: f64,
    pub section: Section,
    /// hydro's steady discharge, m³/s (0 when dry).
    pub discharge: f64,
    /// Map positions of the network nodes it passes through.
    pub vertices: Vec<[f64; 2]>,
}

/// The whole model.
#[derive(Debug, Clone, PartialEq)]
pub struct Model {
    pub nodes: Vec<Node>,
    pub conduits: Vec<Conduit>,
    /// Constant inflows at the sinks: node index and m³/s.
    pub inflows: Vec<(usize, f64)>,
}

impl Conduit {
    /// The same conduit from its second end to its first.
    pub fn reversed(&self) -> Conduit {
        let mut c = self.clone();
        c.ends.reverse();
        c.offsets.reverse();
        c.vertices.reverse();
        c
    }
}

impl Model {
    /// The model with every conduit pointing the way its `flow` runs (negative: from its
    /// second end to its first).
    pub fn along(mut self, flow: &[f64]) -> Model {
        for (c, q) in self.conduits.iter_mut().zip(flow) {
            if *q < 0.0 {
                *c = c.reversed();
            }
        }
        self
    }

    /// The floor elevation of conduit `c` at its ends.
    pub fn inverts(&self, c: &Conduit) -> [f64; 2] {
        [0, 1].map(|e| self.nodes[c.ends[e]].invert + c.offsets[e])
    }
}

/// Length below which a conduit is given this length (SWMM refuses zero-length conduits).
const MIN_LENGTH: f64 = 0.1;

/// Drop of a spring's outlet conduit, metres.
const OUTLET_DROP: f64 = 0.01;

/// The model of a network.
pub fn build(net: &NetworkView, frame: &Frame, params: &ExportParams) -> Model {
    let storage = storage_nodes(net);
    let mut keep = vec![false; net.nodes.len()];
    for t in net.sinks.iter().chain(&net.springs) {
        keep[t.node as usize] = true;
    }
    let mut reaches = chains::merge(segment_reaches(net, frame), &keep, params.swmm_conduit_length);
    for r in &mut reaches {
        cap_slope(r, params.swmm_max_slope);
    }
    let mut invert = vec![f64::INFINITY; net.nodes.len()];
    let mut crown = vec![f64::NEG_INFINITY; net.nodes.len()];
    for r in &reaches {
        for (n, f) in r.ends.iter().zip(r.floors) {
            invert[*n as usize] = invert[*n as usize].min(f);
            crown[*n as usize] = crown[*n as usize].max(f + r.section.height);
        }
    }
    let top = crown.iter().copied().fold(f64::NEG_INFINITY, f64::max);
    let xy = |n: u32| {
        let [x, y, _] = frame.world(net.nodes[n as usize].position);
        [x, y]
    };
    let mut index = vec![usize::MAX; net.nodes.len()];
    let mut nodes = Vec::new();
    for n in (0..net.nodes.len()).filter(|&n| invert[n].is_finite()) {
        index[n] = nodes.len();
        let invert = round4(invert[n]);
        nodes.push(Node {
            name: (n + 1).to_string(),
            kind: storage.get(&n).map_or(NodeKind::Junction, |&a| NodeKind::Storage(a)),
            invert,
            depth: up(crown[n] - invert),
            surcharge: up(top - crown[n]),
            xy: xy(n as u32),
        });
    }
    let mut conduits: Vec<Conduit> = reaches
        .into_iter()
        .map(|r| {
            let ends = r.ends.map(|n| index[n as usize]);
            let offsets = [0, 1].map(|e| round4((r.floors[e] - nodes[ends[e]].invert).max(0.0)));
            Conduit {
                name: conduit_name(&r.segments),
                ends,
                offsets,
                length: round4(r.length),
                section: r.section,
                discharge: r.discharge,
                vertices: r.through.iter().map(|&n| xy(n)).collect(),
            }
        })
        .collect();
    // A sink or spring that no conduit reaches (possible only in a hand-made network) has no
    // node in the model: no inflow, no outfall.
    let modelled = |node: u32| Some(index[node as usize]).filter(|&i| i != usize::MAX);
    for spring in &net.springs {
        let Some(at) = modelled(spring.node) else { continue };
        let (invert, height) = (nodes[at].invert, nodes[at].depth);
        let [x, y] = nodes[at].xy;
        let name = name(&spring.name);
        conduits.push(Conduit {
            name: format!("{name}_outlet"),
            ends: [at, nodes.len()],
            offsets: [0.0; 2],
            length: round4(height.max(1.0)),
            section: Section::circle(height).rounded(),
            discharge: spring.discharge,
            vertices: Vec::new(),
        });
        nodes.push(Node {
            name,
            kind: NodeKind::Outfall,
            invert: round4(invert - OUTLET_DROP),
            depth: 0.0,
            surcharge: 0.0,
            xy: [x + 1.0, y],
        });
    }
    let inflows = net.sinks.iter().filter_map(|s| Some((modelled(s.node)?, s.discharge))).collect();
    Model { nodes, conduits, inflows }
}

/// One reach per segment (self-loops left out), its floor at the conduit's centre minus half
/// its section's height.
fn segment_reaches(net: &NetworkView, frame: &Frame) -> Vec<Reach> {
    let z = |n: u32| frame.world(net.nodes[n as usize].position)[2];
    net.segments
        .iter()
        .filter(|s| !s.is_loop())
        .map(|s| {
            let section = Section::of(s.conduit_type, 0.5 * (s.radius[0] + s.radius[1])).rounded();
            let ends = s.flow_ends();
            Reach {
                segments: vec![s.id],
                ends,
                through: Vec::new(),
                floors: ends.map(|n| z(n) - section.height / 2.0),
                length: s.length.max(MIN_LENGTH),
                section,
                discharge: if s.wet { s.discharge } else { 0.0 },
            }
        })
        .collect()
}

/// A reach steeper than `max_slope` (a shaft) keeps that slope and drops the rest at its lower
/// end.
fn cap_slope(r: &mut Reach, max_slope: f64) {
    let drop = r.floors[0] - r.floors[1];
    if drop.abs() > max_slope * r.length {
        let (low, high) = if drop > 0.0 { (1, 0) } else { (0, 1) };
        r.floors[low] = r.floors[high] - max_slope * r.length;
    }
}

/// A conduit's name: its segment's id, or the first and last of its segments'.
fn conduit_name(segments: &[u32]) -> String {
    match segments {
        [one] => one.to_string(),
        [first, .., last] => format!("{first}-{last}"),
        [] => String::new(),
    }
}

/// Pools (hydro's ponds and chambers) with the horizontal area of their widest conduit, m².
fn storage_nodes(net: &NetworkView) -> BTreeMap<usize, f64> {
    let mut pools = BTreeMap::new();
    for s in &net.segments {
        for (n, r) in s.nodes.iter().zip(s.radius) {
            let node = &net.nodes[*n as usize];
            if node.role == Role::Pool || s.conduit_type == ConduitType::Chamber {
                let area = pools.entry(*n as usize).or_insert(0.0f64);
                *area = area.max(PI * r * r);
            }
        }
    }
    for t in net.sinks.iter().chain(&net.springs) {
        pools.remove(&(t.node as usize));
    }
    pools
}

/// A SWMM name: no spaces.
pub fn name(text: &str) -> String {
    text.chars().map(|c| if c.is_whitespace() || c == ';' || c == '"' { '_' } else { c }).collect()
}

pub fn round4(x: f64) -> f64 {
    (x * 1e4).round() / 1e4
}

/// Depth with 4 decimals, never below what SWMM needs to hold the conduits: rounded up, plus
/// 1 mm so that SWMM's own unit conversions never find a crown above it.
fn up(x: f64) -> f64 {
    (x.max(0.0) * 1e4).ceil() / 1e4 + 0.001
}
