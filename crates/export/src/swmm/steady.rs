//! The steady state of the SWMM model carrying hydro's discharges, as SWMM's dynamic-wave
//! engine finds it, written into the model as its initial state; and what the model needs so
//! that the engine keeps hydro's flows.
//!
//! Why: SWMM counts the water stored at the start in its flow-routing continuity balance. An
//! initial state far from the routed one (hydro's water levels are drawn for the picture, not
//! solved with SWMM's equations; dry dead ends below a pond's level fill in the first seconds)
//! makes the first steps move thousands of m³ between conduits and nodes through pressurized
//! nodes, where the engine does not conserve water, and the balance reports that as an error
//! of several percent. Started from its own steady state, the model stays there. And where
//! hydro splits water (its directional rule at a junction, equal shares at a pool) the engine
//! would split it by conveyance instead, sending another discharge to each spring.
//!
//! How:
//! 1. Flows: every conduit carries hydro's discharge (dry conduits none).
//! 2. Heads, from the outfalls upstream: an outfall's depth is the smaller of the critical and
//!    normal depths of its conduit (SWMM's free outfall); a conduit's downstream depth is the
//!    head at its downstream node above its floor, or the smaller of its critical and normal
//!    depths where it falls freely into that node (an offset above the water there); its
//!    upstream head is the one at which SWMM's steady momentum balance carries its flow:
//!    friction (Manning, on the area and hydraulic radius weighted upstream by Froude number)
//!    against the head difference (`INERTIAL_DAMPING FULL`: no inertial terms), the flow capped at the normal flow where SWMM caps it (`NORMAL_FLOW_LIMITED FROUDE`:
//!    supercritical at the upstream end).
//! 3. Splits: a node with several outgoing conduits takes the highest head they need; each of
//!    the others gets the Manning's n (raised, by bisection) at which it needs that head, so
//!    that the engine carries hydro's share in it: the calibration a modeller does against
//!    measured flows, with hydro as the measurement.
//! 4. Nodes no flow reaches (dead ends, relict conduits) take the level of the water next to
//!    them when it is above the conduit between (a dead end below a pond fills to the pond's
//!    level), else stay dry. A dry conduit left between two waters at different levels (a
//!    relict passage hydro's spill levels keep dry, below the water on both sides) is closed
//!    (`MaxFlow`), or it would carry water hydro sends elsewhere.
//!
//! SWMM starts a conduit at the mean of its end depths, or, when it is given an initial flow,
//! at the normal depth of that flow: a conduit gets its steady flow as initial flow when that
//! normal depth holds a volume closer to the routed one (conduits in normal flow), none
//! otherwise (conduits backed up by a pond or a pressurized reach).

use std::cmp::Ordering;
use std::collections::BinaryHeap;

use super::model::{Conduit, Model, NodeKind};
use super::section::{GRAVITY, Section, bisect};

/// SWMM's smallest depth, 0.0001 ft.
const FUDGE: f64 = 0.0001 * 0.3048;

/// The steady state the model starts at.
#[derive(Debug, Clone, PartialEq)]
pub struct SteadyState {
    /// Water depth above each node's invert, metres (0 dry).
    pub depth: Vec<f64>,
    /// Steady flow of each conduit, m³/s, positive from its first end to its second.
    pub flow: Vec<f64>,
    /// Manning's n of each conduit: `export.manning`, raised where hydro splits water so that
    /// the engine splits it the same way.
    pub roughness: Vec<f64>,
    /// Whether SWMM starts the conduit with its steady flow (else with none).
    pub starts_flowing: Vec<bool>,
    /// Conduits hydro leaves dry between waters at different levels, both above their floor:
    /// closed, or they would divert water hydro sends elsewhere.
    pub closed: Vec<bool>,
}

/// The steady state of `model` carrying hydro's discharges, Manning's n `manning`.
pub fn steady_state(model: &Model, manning: f64) -> SteadyState {
    let flow: Vec<f64> = model.conduits.iter().map(|c| c.discharge).collect();
    let mut roughness = vec![manning; model.conduits.len()];
    let mut head = routed_heads(model, &flow, &mut roughness);
    fill_still_water(model, &mut head);
    let depth = model
        .nodes
        .iter()
        .zip(&head)
        .map(|(node, h)| match (node.kind, h) {
            (NodeKind::Outfall, _) | (_, None) => 0.0,
            (_, Some(h)) => (h - node.invert).clamp(0.0, node.depth + node.surcharge),
        })
        .collect();
    let starts_flowing = model
        .conduits
        .iter()
        .zip(flow.iter().zip(&roughness))
        .map(|(c, (&q, &n))| {
            let pipe = Pipe::along(model, c, q >= 0.0, n);
            let [up, down] = if q >= 0.0 { c.ends } else { [c.ends[1], c.ends[0]] };
            match (head[up], head[down]) {
                (Some(h1), Some(h2)) if q != 0.0 => pipe.starts_at_normal_depth(q.abs(), [h1, h2]),
                _ => false,
            }
        })
        .collect();
    let closed =
        model.conduits.iter().zip(&flow).map(|(c, &q)| q == 0.0 && divides_waters(model, c, &head)).collect();
    SteadyState { depth, flow, roughness, starts_flowing, closed }
}

/// Whether dry conduit `c` joins two waters whose levels differ by more than a millimetre, the
/// higher above its floor: the engine would let it carry water from one to the other.
fn divides_waters(model: &Model, c: &Conduit, head: &[Option<f64>]) -> bool {
    let [Some(a), Some(b)] = c.ends.map(|n| head[n]) else { return false };
    let sill = model.inverts(c).into_iter().fold(f64::NEG_INFINITY, f64::max);
    (a - b).abs() > 0.001 && a.max(b) > sill
}

/// Heads of the nodes the water runs through when conduits carry `flow` (positive from their
/// first end to their second), from the outfalls upstream. A node with several outgoing
/// conduits takes the highest of their upstream heads, and the others get the roughness at
/// which they carry their flow under that head (`roughness` holds the n of every conduit).
fn routed_heads(model: &Model, flow: &[f64], roughness: &mut [f64]) -> Vec<Option<f64>> {
    let n = model.nodes.len();
    let mut pending = vec![0usize; n];
    let mut incoming: Vec<Vec<(usize, usize)>> = vec![Vec::new(); n];
    let mut outgoing: Vec<Vec<(usize, usize)>> = vec![Vec::new(); n];
    for (k, c) in model.conduits.iter().enumerate().filter(|(k, _)| flow[*k] != 0.0) {
        let [up, down] = if flow[k] > 0.0 { c.ends } else { [c.ends[1], c.ends[0]] };
        pending[up] += 1;
        incoming[down].push((k, up));
        outgoing[up].push((k, down));
    }
    let pipe = |k: usize, up: usize, n: f64| {
        let c = &model.conduits[k];
        Pipe::along(model, c, c.ends[0] == up, n)
    };
    let mut head = vec![None; n];
    let mut ready = Vec::new();
    for (k, c) in model.conduits.iter().enumerate() {
        let outfall = &model.nodes[c.ends[1]];
        if outfall.kind == NodeKind::Outfall {
            let free_fall = pipe(k, c.ends[0], roughness[k]).free_fall_depth(flow[k].abs());
            head[c.ends[1]] = Some(outfall.invert + free_fall);
            ready.push(c.ends[1]);
        }
    }
    while let Some(down) = ready.pop() {
        for &(_, up) in &incoming[down] {
            pending[up] -= 1;
            if pending[up] > 0 {
                continue;
            }
            let needed = |k: usize, d: usize, n: f64| {
                let h_down = head[d].expect("downstream nodes come first");
                pipe(k, up, n).upstream_head(flow[k].abs(), h_down).head
            };
            let h = outgoing[up]
                .iter()
                .map(|&(k, d)| needed(k, d, roughness[k]))
                .fold(f64::NEG_INFINITY, f64::max);
            for &(k, d) in &outgoing[up] {
                roughness[k] = matching_roughness(roughness[k], h, |n| needed(k, d, n));
            }
            head[up] = Some(h);
            ready.push(up);
        }
    }
    head
}

/// Largest ratio of a calibrated Manning's n to `export.manning`.
const MAX_ROUGHNESS_FACTOR: f64 = 1e4;

/// The roughness, from `n` up, at which a conduit needs the upstream head `h`
/// (`needed(n)`: the head it needs to carry its flow), within a millimetre; `n` itself when it
/// already needs that much.
fn matching_roughness(n: f64, h: f64, needed: impl Fn(f64) -> f64) -> f64 {
    const TOLERANCE: f64 = 0.001;
    if needed(n) >= h - TOLERANCE {
        return n;
    }
    let mut hi = 2.0;
    while needed(n * hi) < h && hi < MAX_ROUGHNESS_FACTOR {
        hi *= 2.0;
    }
    n * bisect_log(1.0, hi, |f| needed(n * f) < h)
}

/// [`bisect`] on a logarithmic scale, between positive bounds.
fn bisect_log(lo: f64, hi: f64, below: impl Fn(f64) -> bool) -> f64 {
    bisect(lo.ln(), hi.ln(), |x| below(x.exp())).exp()
}

/// A water level at a node, ordered by level then node (a deterministic order).
#[derive(Debug, Clone, Copy, PartialEq)]
struct Way {
    level: f64,
    node: usize,
}

impl Eq for Way {}

impl Ord for Way {
    fn cmp(&self, other: &Self) -> Ordering {
        self.level.total_cmp(&other.level).then(self.node.cmp(&other.node))
    }
}

impl PartialOrd for Way {
    fn partial_cmp(&self, other: &Self) -> Option<Ordering> {
        Some(self.cmp(other))
    }
}

/// A conduit seen along the water: SWMM's hydraulics of one conduit.
struct Pipe {
    section: Section,
    length: f64,
    /// Floor elevations at the upstream and downstream ends.
    floors: [f64; 2],
    /// The conduit enters its downstream node above that node's invert (it may fall freely).
    offset_down: bool,
    into_outfall: bool,
    manning: f64,
}

/// A conduit's steady upstream head and downstream flow depth.
struct Ends {
    head: f64,
    downstream_depth: f64,
}

impl Pipe {
    /// Conduit `c` with the water running from its first end to its second (`forward`) or
    /// back.
    fn along(model: &Model, c: &Conduit, forward: bool, manning: f64) -> Pipe {
        let (floors, down, offset) = match (forward, model.inverts(c)) {
            (true, z) => (z, c.ends[1], c.offsets[1]),
            (false, [a, b]) => ([b, a], c.ends[0], c.offsets[0]),
        };
        Pipe {
            section: c.section,
            length: c.length,
            floors,
            offset_down: offset > 0.0,
            into_outfall: model.nodes[down].kind == NodeKind::Outfall,
            manning,
        }
    }

    /// SWMM's slope: floor drop over horizontal length, at least 0.001 ft of drop.
    fn slope(&self) -> f64 {
        let [z1, z2] = self.floors;
        let drop = (z1 - z2).abs().max(0.001 * 0.3048);
        let l = self.length;
        let s = if drop >= l { drop / l } else { drop / (l * l - drop * drop).sqrt() };
        if z1 >= z2 { s } else { -s }
    }

    /// The depth of a free fall out of the conduit: the smaller of its critical and normal
    /// depths.
    fn free_fall_depth(&self, q: f64) -> f64 {
        let s = self.section;
        s.critical_depth(q).min(s.normal_depth(q, self.slope().abs(), self.manning))
    }

    /// The steady upstream head for a flow `q` when the downstream node's head is `h_down`,
    /// and the flow depth at the downstream end.
    fn upstream_head(&self, q: f64, h_down: f64) -> Ends {
        let [z1, z2] = self.floors;
        let free_fall = self.free_fall_depth(q);
        let falls = self.into_outfall || (self.offset_down && h_down - z2 < free_fall);
        let h2 = if falls { z2 + free_fall } else { h_down.max(z2 + FUDGE) };
        let downstream_depth = (h2 - z2).clamp(FUDGE, self.section.height);
        let carries = |h1: f64| self.carries(q, [h1, h2], !falls);
        let lo = z1 + FUDGE;
        if carries(lo) {
            return Ends { head: lo, downstream_depth };
        }
        let mut hi = lo.max(h2) + self.section.height;
        while !carries(hi) && hi - lo < 1e5 {
            hi = lo + 2.0 * (hi - lo);
        }
        Ends { head: bisect(lo, hi, |h1| !carries(h1)), downstream_depth }
    }

    /// Whether the conduit carries `q` steadily between heads `h` (upstream, downstream):
    /// SWMM's momentum balance leaves at least that flow, and the normal flow does too where
    /// SWMM's `NORMAL_FLOW_LIMITED FROUDE` caps the flow at it (`limited`: the conduit does not
    /// fall freely at its downstream end).
    fn carries(&self, q: f64, h: [f64; 2], limited: bool) -> bool {
        let s = self.section;
        let [y1, y2] = [0, 1].map(|e| (h[e] - self.floors[e]).clamp(FUDGE, s.height));
        let surface_slope = (h[0] - h[1]) / self.length;
        if !driving_exceeds_friction(&s, [y1, y2], surface_slope, q, self.manning) {
            return false;
        }
        let capped = y1 < s.height && limited && s.froude(q / s.area(y1), y1) >= 1.0;
        !capped || s.normal_flow(y1, self.slope(), self.manning) >= q
    }

    /// Whether the normal depth of `q`, where SWMM starts a conduit given that initial flow,
    /// holds a volume closer to the steady one between heads `h` than the mean of the end
    /// depths, where SWMM starts it otherwise.
    fn starts_at_normal_depth(&self, q: f64, h: [f64; 2]) -> bool {
        let s = self.section;
        let [y1, y2] = [0, 1].map(|e| (h[e] - self.floors[e]).clamp(0.0, s.height));
        let routed = 0.5 * (s.area(y1) + s.area(self.upstream_head(q, h[1]).downstream_depth));
        let normal = s.area(s.normal_depth(q, self.slope().abs(), self.manning));
        (normal - routed).abs() < (s.area(0.5 * (y1 + y2)) - routed).abs()
    }
}

/// Whether, at flow `q` between end depths `y` on a water-surface slope `slope`, SWMM's
/// momentum update would raise the flow: g·A·S ≥ g·n²·Q·|V|/R^(4/3), with A and R weighted
/// towards the upstream end by σ (1 below Froude 0.5, 0 above 1, read at mid-depth; not in a
/// full conduit) and no inertial terms (`INERTIAL_DAMPING FULL`). At the steady flow both
/// sides are equal.
fn driving_exceeds_friction(s: &Section, y: [f64; 2], slope: f64, q: f64, manning: f64) -> bool {
    let (a1, r1) = (s.area(y[0]), s.hydraulic_radius(y[0]));
    let mid = 0.5 * (y[0] + y[1]);
    let (am, rm) = (s.area(mid), s.hydraulic_radius(mid));
    let full = y[0] >= s.height && y[1] >= s.height;
    let v = q / am;
    let rho = if full { 1.0 } else { (2.0 * (1.0 - s.froude(v, mid))).clamp(0.0, 1.0) };
    let (aw, rw) = (a1 + (am - a1) * rho, r1 + (rm - r1) * rho);
    GRAVITY * aw * slope >= GRAVITY * manning * manning * q * v.abs() / rw.powf(4.0 / 3.0)
}

/// Heads of the nodes no flow reaches: the level of the still water beside them when it is
/// above the conduit between, highest level first.
fn fill_still_water(model: &Model, head: &mut [Option<f64>]) {
    let mut links: Vec<Vec<(usize, &Conduit)>> = vec![Vec::new(); model.nodes.len()];
    for c in &model.conduits {
        let [a, b] = c.ends;
        links[a].push((b, c));
        links[b].push((a, c));
    }
    let routed: Vec<bool> = head.iter().map(Option::is_some).collect();
    let mut heap: BinaryHeap<Way> =
        head.iter().enumerate().filter_map(|(n, h)| h.map(|h| Way { level: h, node: n })).collect();
    while let Some(Way { level: h, node }) = heap.pop() {
        if head[node].is_some_and(|current| current > h) {
            continue;
        }
        for &(other, c) in &links[node] {
            let floor = model.inverts(c).into_iter().fold(f64::NEG_INFINITY, f64::max);
            let higher = head[other].is_none_or(|o| o < h);
            let fills = !routed[other] && model.nodes[other].kind != NodeKind::Outfall && h > floor;
            if fills && higher {
                head[other] = Some(h);
                heap.push(Way { level: h, node: other });
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::super::model::Node;
    use super::*;

    fn node(name: &str, kind: NodeKind, invert: f64) -> Node {
        Node { name: name.into(), kind, invert, depth: 3.0, surcharge: 10.0, xy: [0.0; 2] }
    }

    fn conduit(ends: [usize; 2], length: f64, discharge: f64) -> Conduit {
        Conduit {
            name: format!("{}-{}", ends[0], ends[1]),
            ends,
            offsets: [0.0; 2],
            length,
            section: Section::circle(2.0),
            discharge,
            vertices: Vec::new(),
        }
    }

    /// A sink (0) whose water hydro splits 0.7 / 0.3 over two like conduits to junctions 1
    /// and 2, each drained to an outfall (3, 4).
    fn split() -> Model {
        let nodes = vec![
            node("sink", NodeKind::Junction, 10.0),
            node("a", NodeKind::Junction, 9.0),
            node("b", NodeKind::Junction, 9.0),
            node("A", NodeKind::Outfall, 8.0),
            node("B", NodeKind::Outfall, 8.0),
        ];
        let conduits = vec![
            conduit([0, 1], 50.0, 0.7),
            conduit([0, 2], 50.0, 0.3),
            conduit([1, 3], 50.0, 0.7),
            conduit([2, 4], 50.0, 0.3),
        ];
        Model { nodes, conduits, inflows: vec![(0, 1.0)] }
    }

    #[test]
    fn a_split_is_kept_by_roughening_the_conduit_given_less_water() {
        let model = split();
        let state = steady_state(&model, 0.03);
        assert_eq!(state.flow, [0.7, 0.3, 0.7, 0.3]);
        assert_eq!(state.roughness[0], 0.03, "the conduit with the larger share sets the head");
        assert!(state.roughness[1] > 0.03, "{:?}", state.roughness);
        assert_eq!(&state.roughness[2..], [0.03, 0.03]);
        // under the sink's head, each conduit carries exactly its share with its roughness
        let head = model.nodes[0].invert + state.depth[0];
        for k in 0..2 {
            let c = &model.conduits[k];
            let h_down = model.nodes[c.ends[1]].invert + state.depth[c.ends[1]];
            let pipe = Pipe::along(&model, c, true, state.roughness[k]);
            let needed = pipe.upstream_head(state.flow[k], h_down).head;
            assert!((needed - head).abs() < 2e-3, "conduit {k}: needs {needed} m, the sink is at {head} m");
        }
        assert!(state.depth[0] > 0.0 && state.closed.iter().all(|c| !c));
    }

    #[test]
    fn a_dry_conduit_between_two_waters_is_closed_and_a_dead_end_fills() {
        let mut model = split();
        // a dry link low between the two branches, and a dry dead end below junction a
        model.nodes.push(node("dead end", NodeKind::Junction, 8.5));
        model.conduits.push(conduit([1, 2], 5.0, 0.0));
        model.conduits.push(conduit([1, 5], 5.0, 0.0));
        let state = steady_state(&model, 0.03);
        let level = |n: usize| model.nodes[n].invert + state.depth[n];
        assert!(level(1) > level(2) + 0.001, "the larger share stands higher");
        assert_eq!(state.closed, [false, false, false, false, true, false]);
        assert!((level(5) - level(1)).abs() < 1e-9, "the dead end holds the water beside it");
    }
}
