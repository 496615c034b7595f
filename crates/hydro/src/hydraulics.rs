//! The hydro stage's computation: hydraulic graph, orientation, flows, water types, water
//! geometry and flow-sized radii, assembled into the [`Hydro`] artifact.

use glam::{DVec2, DVec3};

use karst_scene::params::{HydroParams, PoolWeights};
use karst_skeleton::{ConduitType, Skeleton, Zone};

use crate::flow::{self, Flows, Split, propagate};
use crate::geometry::{self, FreeSurface};
use crate::graph::{self, Graph, Terminal};
use crate::orient::{Orientation, orient};
use crate::payload::{ConduitWater, FlowUnits, Hydro, NodeWater, Role, SegmentWater, Share, Sink, Spring};
use crate::water::{FlowScale, WaterType, classify};
use crate::{HydroError, sizing};

/// What the scene adds to the skeleton.
#[derive(Debug, Clone, Default)]
pub struct Inputs {
    /// Names of the scene's springs: nodes with these key points are wells.
    pub spring_names: Vec<String>,
    /// Recharge per sink name replacing the routes' weights (catchment areas).
    pub recharge: Vec<(String, f64)>,
}

/// Elevation differences below this are level, metres.
const LEVEL: f64 = 1e-9;

/// The hydro artifact of `skeleton`.
pub fn compute(skeleton: &Skeleton, params: &HydroParams, inputs: &Inputs) -> Result<Hydro, HydroError> {
    let graph = Graph::of(skeleton);
    let sinks =
        graph::sinks(skeleton, |name| inputs.recharge.iter().find(|(n, _)| n == name).map(|(_, w)| *w));
    let springs = graph::springs(skeleton, &inputs.spring_names)?;
    let orientation = orient(skeleton, &graph, &springs.iter().map(|t| t.node).collect::<Vec<_>>());
    if let Some(t) = sinks.iter().find(|t| orientation.rank[t.node as usize].is_none()) {
        return Err(HydroError::NoDownstreamPath { sink: t.name.clone(), node: t.node });
    }
    let ponds = Ponds::of(skeleton, &graph, &orientation);
    let user = user_pools(&params.pools, &graph, &orientation, &ponds)?;
    let flows = propagate(&graph, &orientation, &sinks, &springs, |n| match user[n as usize] {
        Some(i) => Split::User(&params.pools[i].outlets),
        None if ponds.pool[n as usize] => Split::Equal,
        None => Split::Directional,
    });
    let water = Water::new(skeleton, params, &graph, &orientation, &flows, &sinks, &ponds);
    let segments = water.segments();
    let conduits = conduits(skeleton, &water, segments);
    let nodes = nodes(&flows, &sinks, &springs, &ponds, &graph, &conduits);
    Ok(Hydro {
        flow_units: FlowUnits { min: water.scale.min, max: water.scale.max },
        conduits,
        nodes,
        sinks: sinks
            .iter()
            .enumerate()
            .map(|(i, t)| Sink {
                name: t.name.clone(),
                node: t.node,
                recharge: t.weight,
                springs: shares(springs.iter().enumerate().map(|(w, s)| (&s.name, flows.share(w, i)))),
            })
            .collect(),
        springs: springs
            .iter()
            .enumerate()
            .map(|(w, s)| Spring {
                name: s.name.clone(),
                node: s.node,
                flow: (0..sinks.len()).map(|i| flows.share(w, i)).sum(),
                sinks: shares(sinks.iter().enumerate().map(|(i, t)| (&t.name, flows.share(w, i)))),
            })
            .collect(),
    })
}

/// The non-zero shares, in order.
fn shares<'a>(items: impl Iterator<Item = (&'a String, f64)>) -> Vec<Share> {
    items.filter(|(_, f)| *f > 0.0).map(|(name, flow)| Share { name: name.clone(), flow }).collect()
}

/// Where water collects: chambers, filled low points of the vadose zone, the water table.
struct Ponds {
    /// Water is split equally at the node.
    pool: Vec<bool>,
    /// Vadose node lying below its fill level.
    ponded: Vec<bool>,
}

impl Ponds {
    fn of(skeleton: &Skeleton, graph: &Graph, orientation: &Orientation) -> Ponds {
        let n = graph.positions.len();
        let ponded: Vec<bool> = (0..n)
            .map(|i| {
                skeleton.nodes[i].zone == Zone::Vadose && orientation.level[i] > graph.positions[i].z + LEVEL
            })
            .collect();
        let mut pool = ponded.clone();
        for l in &graph.links {
            let chamber = skeleton.conduits[l.conduit].types.get(l.segment) == Some(&ConduitType::Chamber);
            let [za, zb] = [l.a, l.b].map(|i| skeleton.nodes[i as usize].zone);
            for (node, own, other) in [(l.a, za, zb), (l.b, zb, za)] {
                if chamber || (own == Zone::Phreatic && other == Zone::Vadose) {
                    pool[node as usize] = true;
                }
            }
        }
        Ponds { pool, ponded }
    }
}

/// The pool node each `[[hydro.pools]]` entry selects (the pool nearest to its `at`, within
/// its radius, ties to the smaller node), as the entry's index per node; checks that no two
/// entries select the same pool and that some outgoing conduit of each gets a weight > 0.
fn user_pools(
    pools: &[PoolWeights],
    graph: &Graph,
    orientation: &Orientation,
    ponds: &Ponds,
) -> Result<Vec<Option<usize>>, HydroError> {
    let mut user = vec![None; graph.positions.len()];
    for (index, pool) in pools.iter().enumerate() {
        let at = DVec3::from_array(pool.at);
        let nearest = (0..graph.positions.len())
            .filter(|&i| ponds.pool[i])
            .map(|i| (graph.positions[i].distance(at), i))
            .min_by(|a, b| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1)));
        let node = match nearest {
            Some((d, i)) if d <= pool.radius => i,
            _ => {
                let nearest = match nearest {
                    Some((d, i)) => format!("the nearest pool is node {i}, {d:.1} m away"),
                    None => "the network has no pool".to_string(),
                };
                return Err(HydroError::NoPoolNear { index, at: pool.at, radius: pool.radius, nearest });
            }
        };
        if let Some(first) = user[node] {
            return Err(HydroError::SamePool { first, second: index, node: node as u32 });
        }
        user[node] = Some(index);
        let outgoing: Vec<(usize, u32)> = graph.at_node[node]
            .iter()
            .filter_map(|&l| match orientation.direction(graph, l) {
                Some((from, to)) if from as usize == node => Some((l, to)),
                _ => None,
            })
            .collect();
        let out = flow::out_directions(graph, node as u32, &outgoing);
        let weights = flow::outlet_weights(graph.positions[node], &out, &pool.outlets);
        if !weights.is_empty() && weights.iter().all(|&w| w <= 0.0) {
            return Err(HydroError::PoolClosed { index, node: node as u32 });
        }
    }
    Ok(user)
}

/// Everything needed to describe the water of each link.
struct Water<'a> {
    skeleton: &'a Skeleton,
    params: &'a HydroParams,
    graph: &'a Graph,
    orientation: &'a Orientation,
    ponds: &'a Ponds,
    /// Flow of each link.
    flow: Vec<f64>,
    /// m³/s per unit of flow.
    to_discharge: f64,
    scale: FlowScale,
    /// Radius at each node of each conduit.
    radii: Vec<Vec<f64>>,
    /// Whether `radii` come from the flow.
    sized: bool,
}

impl<'a> Water<'a> {
    fn new(
        skeleton: &'a Skeleton,
        params: &'a HydroParams,
        graph: &'a Graph,
        orientation: &'a Orientation,
        flows: &Flows,
        sinks: &[Terminal],
        ponds: &'a Ponds,
    ) -> Self {
        let flow: Vec<f64> = (0..graph.links.len()).map(|l| flows.link(l)).collect();
        let recharge: f64 = sinks.iter().map(|t| t.weight).sum();
        let to_discharge = if recharge > 0.0 { params.total_discharge / recharge } else { 0.0 };
        let mut water = Water {
            skeleton,
            params,
            graph,
            orientation,
            ponds,
            flow,
            to_discharge,
            scale: FlowScale { min: 0.0, max: 0.0 },
            radii: skeleton.conduits.iter().map(|c| c.radius.clone()).collect(),
            sized: params.flow_radius.is_some(),
        };
        let running: Vec<f64> =
            (0..graph.links.len()).filter(|&l| water.is_running(l)).map(|l| water.flow[l]).collect();
        let min = running.iter().copied().fold(f64::INFINITY, f64::min);
        water.scale = FlowScale {
            min: if min.is_finite() { min } else { 0.0 },
            max: running.iter().copied().fold(0.0, f64::max),
        };
        if let Some(range) = params.flow_radius {
            let q_max = water.flow.iter().copied().fold(0.0, f64::max);
            water.radii = water.per_conduit(
                |l| water.flow[l],
                |flows| sizing::conduit_radii(flows, q_max, range, params.radius_exponent),
            );
        }
        water
    }

    /// Applies `f` to the values `value(link)` of each conduit's segments.
    fn per_conduit<T>(&self, value: impl Fn(usize) -> f64, f: impl Fn(&[f64]) -> T) -> Vec<T> {
        let mut out = Vec::with_capacity(self.skeleton.conduits.len());
        let mut first = 0;
        for conduit in &self.skeleton.conduits {
            let n = conduit.nodes.len().saturating_sub(1);
            let values: Vec<f64> = (first..first + n).map(&value).collect();
            out.push(f(&values));
            first += n;
        }
        out
    }

    fn direction(&self, l: usize) -> Option<(u32, u32)> {
        self.orientation.direction(self.graph, l).filter(|_| self.flow[l] > 0.0)
    }

    fn phreatic(&self, l: usize) -> bool {
        let link = &self.graph.links[l];
        [link.a, link.b].iter().all(|&n| self.skeleton.nodes[n as usize].zone == Zone::Phreatic)
    }

    /// Water ponds in the link: a chamber, water rising, or leaving a filled low point.
    fn ponding(&self, l: usize) -> bool {
        let Some((from, to)) = self.direction(l) else { return false };
        let link = &self.graph.links[l];
        let chamber =
            self.skeleton.conduits[link.conduit].types.get(link.segment) == Some(&ConduitType::Chamber);
        let rises = self.graph.positions[to as usize].z > self.graph.positions[from as usize].z + LEVEL;
        chamber || rises || self.ponds.ponded[from as usize]
    }

    /// A wet vadose link classified with Table 1.
    fn is_running(&self, l: usize) -> bool {
        self.direction(l).is_some() && !self.phreatic(l) && !self.ponding(l)
    }

    fn slope(&self, l: usize) -> f64 {
        let link = &self.graph.links[l];
        let d = self.graph.positions[link.b as usize] - self.graph.positions[link.a as usize];
        let length = d.length();
        if length > 0.0 { (d.z.abs() / length).clamp(0.0, 1.0).asin() } else { 0.0 }
    }

    /// Radii at the two ends of link `l` (in conduit order).
    fn end_radii(&self, l: usize) -> [f64; 2] {
        let link = &self.graph.links[l];
        let r = &self.radii[link.conduit];
        [r[link.segment], r[link.segment + 1]]
    }

    /// The water of every link, in link order. Links are visited from upstream to downstream
    /// so that a free fall knows the horizontal speed of the water reaching its lip.
    fn segments(&self) -> Vec<SegmentWater> {
        let mut out: Vec<Option<SegmentWater>> = vec![None; self.graph.links.len()];
        let mut arrival: Vec<Option<Arrival>> = vec![None; self.graph.positions.len()];
        for &node in &self.orientation.upstream_first {
            for &l in &self.graph.at_node[node as usize] {
                let Some((from, to)) = self.direction(l) else { continue };
                if from != node {
                    continue;
                }
                let (segment, leaving) = self.wet(l, from, to, arrival[from as usize]);
                let best = arrival[to as usize].is_none_or(|a| a.flow < self.flow[l]);
                if best {
                    arrival[to as usize] = Some(Arrival { flow: self.flow[l], ..leaving });
                }
                out[l] = Some(segment);
            }
        }
        out.into_iter().enumerate().map(|(l, s)| s.unwrap_or_else(|| self.dry(l))).collect()
    }

    fn dry(&self, l: usize) -> SegmentWater {
        SegmentWater {
            downstream: false,
            flow: 0.0,
            discharge: 0.0,
            water: WaterType::Dry,
            slope: self.slope(l),
            flow_units: 0.0,
            look: None,
            speed: 0.0,
            depth: 0.0,
            width: 0.0,
            level: None,
            fall: None,
        }
    }

    /// The water of wet link `l` running `from` → `to`, and how it leaves at `to`.
    fn wet(&self, l: usize, from: u32, to: u32, arriving: Option<Arrival>) -> (SegmentWater, Arrival) {
        let link = &self.graph.links[l];
        let (q, slope) = (self.flow[l], self.slope(l));
        let discharge = q * self.to_discharge;
        let [ra, rb] = self.end_radii(l);
        let r = 0.5 * (ra + rb);
        let (pa, pb) = (self.graph.positions[from as usize], self.graph.positions[to as usize]);
        let horizontal = DVec2::new(pb.x - pa.x, pb.y - pa.y).normalize_or_zero();
        let (water, units) = if self.phreatic(l) {
            (WaterType::Sump, 0.0)
        } else if self.ponding(l) {
            (WaterType::Pool, 0.0)
        } else {
            let units = self.scale.units(q);
            (classify(slope, units), units)
        };
        let mut seg = SegmentWater {
            downstream: link.a == from,
            flow: q,
            discharge,
            water,
            slope,
            flow_units: units,
            look: water.look(),
            ..self.dry(l)
        };
        let p = self.params;
        if water.is_free_fall() {
            let a = arriving.unwrap_or(Arrival { flow: 0.0, speed: 0.0, direction: DVec2::ZERO });
            let direction =
                [a.direction, horizontal].into_iter().find(|d| *d != DVec2::ZERO).unwrap_or(DVec2::X);
            let v0 = if a.speed > 0.0 { a.speed } else { geometry::speed(0.0, p.speed_factor, p.min_slope) };
            let (fall, jet) = geometry::fall(pa, pb, direction, v0, discharge, r);
            seg.speed = (v0 * v0 + geometry::G * fall.drop).sqrt();
            (seg.depth, seg.width) = (jet.depth, jet.width);
            seg.fall = Some(fall);
            return (seg, Arrival { flow: q, speed: v0, direction });
        }
        // Running water moves at δ = k·s; a full conduit or a sump carries it under pressure.
        let running =
            geometry::speed(if water == WaterType::Pool { 0.0 } else { slope }, p.speed_factor, p.min_slope);
        let full = discharge / (std::f64::consts::PI * r * r).max(f64::MIN_POSITIVE);
        let surface = if water == WaterType::Sump {
            FreeSurface { depth: 2.0 * r, width: 0.0 }
        } else {
            geometry::free_surface(discharge / running, r)
        };
        seg.speed = if surface.width == 0.0 { full } else { running };
        (seg.depth, seg.width) = (surface.depth, surface.width);
        seg.level = Some(self.levels(l, surface.depth));
        let direction = if horizontal == DVec2::ZERO {
            arriving.map_or(DVec2::ZERO, |a| a.direction)
        } else {
            horizontal
        };
        let speed = seg.speed * slope.cos();
        (seg, Arrival { flow: q, speed, direction })
    }

    /// Water surface at both ends of `l` (conduit order): `depth` above the floor, raised to
    /// the fill level of a ponded node, never above the roof.
    fn levels(&self, l: usize, depth: f64) -> [f64; 2] {
        let link = &self.graph.links[l];
        let radii = self.end_radii(l);
        [link.a, link.b]
            .iter()
            .zip(radii)
            .map(|(&n, r)| {
                let z = self.graph.positions[n as usize].z;
                let pond =
                    if self.ponds.ponded[n as usize] { self.orientation.level[n as usize] } else { f64::MIN };
                (z - r + depth).max(pond).min(z + r)
            })
            .collect::<Vec<_>>()
            .try_into()
            .expect("two ends")
    }
}

/// How water reaches a node: the largest inflow's horizontal speed and direction.
#[derive(Debug, Clone, Copy, PartialEq)]
struct Arrival {
    flow: f64,
    speed: f64,
    direction: DVec2,
}

/// Groups the link waters by conduit.
fn conduits(skeleton: &Skeleton, water: &Water, segments: Vec<SegmentWater>) -> Vec<ConduitWater> {
    let mut segments = segments.into_iter();
    skeleton
        .conduits
        .iter()
        .enumerate()
        .map(|(c, conduit)| {
            let segs: Vec<SegmentWater> =
                segments.by_ref().take(conduit.nodes.len().saturating_sub(1)).collect();
            ConduitWater {
                flow: segs.iter().map(|s| s.flow).fold(0.0, f64::max),
                downstream: segs.first().is_some_and(|s| s.downstream),
                dry: segs.iter().all(|s| s.water == WaterType::Dry),
                radius: water.sized.then(|| water.radii[c].clone()),
                segments: segs,
            }
        })
        .collect()
}

/// The role and inflow of every node.
fn nodes(
    flows: &Flows,
    sinks: &[Terminal],
    springs: &[Terminal],
    ponds: &Ponds,
    graph: &Graph,
    conduits: &[ConduitWater],
) -> Vec<NodeWater> {
    let mut plunge = vec![false; graph.positions.len()];
    for l in &graph.links {
        let s = &conduits[l.conduit].segments[l.segment];
        if s.water.is_free_fall() {
            plunge[if s.downstream { l.b } else { l.a } as usize] = true;
        }
    }
    (0..graph.positions.len())
        .map(|i| {
            let inflow = flows.inflow[i];
            let role = if springs.iter().any(|t| t.node as usize == i) {
                Role::Well
            } else if sinks.iter().any(|t| t.node as usize == i) {
                Role::Source
            } else if inflow <= 0.0 {
                Role::Dry
            } else if ponds.pool[i] || plunge[i] {
                Role::Pool
            } else {
                Role::Branch
            };
            NodeWater { role, inflow }
        })
        .collect()
}
