//! The hydro artifact, `hydro.json`: per conduit and per segment, where the water goes, how
//! much, what it looks like (the water types of Emilien et al. 2015, Table 1) and where its
//! surface lies; per node, its role in the hydraulic graph (§4.2); per sink and spring, the
//! recharge and discharge. The layout is described field by field in docs/hydro.md.

use serde::{Deserialize, Serialize};

use karst_artifact::check::{self, MAX_COORDINATE};
use karst_artifact::{Invalid, Payload, StageId};

use crate::water::{Look, WaterType};

/// The hydro artifact.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Hydro {
    /// How network flows were mapped to the paper's flow units.
    pub flow_units: FlowUnits,
    /// One entry per skeleton conduit, same index.
    pub conduits: Vec<ConduitWater>,
    /// One entry per skeleton node, same index.
    pub nodes: Vec<NodeWater>,
    /// Every sink, in order of first route.
    pub sinks: Vec<Sink>,
    /// Every spring reached by water or named by a route, in order of first appearance.
    pub springs: Vec<Spring>,
}

impl Payload for Hydro {
    const STAGE: StageId = StageId::Hydro;
    const SCHEMA: u32 = 2;

    /// Flows, discharges, speeds, depths and widths finite and ≥ 0, slopes within [0, π/2],
    /// finite levels and falls, radii finite and > 0, sinks and springs at existing nodes.
    /// (That `conduits` and `nodes` match skeleton.json is checked by the stages reading both.)
    fn validate(&self) -> Result<(), Invalid> {
        amount(|| "flow_units.min".into(), self.flow_units.min)?;
        amount(|| "flow_units.max".into(), self.flow_units.max)?;
        for (c, conduit) in self.conduits.iter().enumerate() {
            amount(|| format!("conduits[{c}].flow"), conduit.flow)?;
            for (i, r) in conduit.radius.iter().flatten().enumerate() {
                check::positive(|| format!("conduits[{c}].radius[{i}]"), *r, MAX_COORDINATE)?;
            }
            for (i, segment) in conduit.segments.iter().enumerate() {
                segment.validate(&|| format!("conduits[{c}].segments[{i}]"))?;
            }
        }
        for (n, node) in self.nodes.iter().enumerate() {
            amount(|| format!("nodes[{n}].inflow"), node.inflow)?;
        }
        for (i, sink) in self.sinks.iter().enumerate() {
            check::index(|| format!("sinks[{i}].node"), sink.node as u64, self.nodes.len())?;
            amount(|| format!("sinks[{i}].recharge"), sink.recharge)?;
            for (j, share) in sink.springs.iter().enumerate() {
                amount(|| format!("sinks[{i}].springs[{j}].flow"), share.flow)?;
            }
        }
        for (i, spring) in self.springs.iter().enumerate() {
            check::index(|| format!("springs[{i}].node"), spring.node as u64, self.nodes.len())?;
            amount(|| format!("springs[{i}].flow"), spring.flow)?;
            for (j, share) in spring.sinks.iter().enumerate() {
                amount(|| format!("springs[{i}].sinks[{j}].flow"), share.flow)?;
            }
        }
        Ok(())
    }
}

/// A flow, length or speed: finite and ≥ 0.
fn amount(field: impl FnOnce() -> String, value: f64) -> Result<(), Invalid> {
    check::within(field, value, 0.0, f64::MAX)
}

impl SegmentWater {
    fn validate(&self, at: &dyn Fn() -> String) -> Result<(), Invalid> {
        let field = |name: &str| format!("{}.{name}", at());
        for (name, value) in [
            ("flow", self.flow),
            ("discharge", self.discharge),
            ("flow_units", self.flow_units),
            ("speed", self.speed),
            ("depth", self.depth),
            ("width", self.width),
        ] {
            amount(|| field(name), value)?;
        }
        check::within(|| field("slope"), self.slope, 0.0, std::f64::consts::FRAC_PI_2)?;
        if let Some(level) = &self.level {
            check::position(|| field("level"), level)?;
        }
        if let Some(fall) = &self.fall {
            check::position(|| field("fall.lip"), &fall.lip)?;
            check::position(|| field("fall.impact"), &fall.impact)?;
            check::within(
                || field("fall.direction"),
                fall.direction[0].hypot(fall.direction[1]),
                0.999,
                1.001,
            )?;
            for (name, value) in
                [("fall.speed", fall.speed), ("fall.drop", fall.drop), ("fall.throw", fall.throw)]
            {
                amount(|| field(name), value)?;
            }
        }
        if let Some(look) = &self.look {
            for (name, value) in [
                ("look.foam", look.foam),
                ("look.rocks", look.rocks),
                ("look.disturbance", look.disturbance),
                ("look.particles", look.particles),
            ] {
                check::within(|| field(name), value, 0.0, 1.0)?;
            }
        }
        Ok(())
    }
}

/// Flow `q` (network units) maps to `1 + 7 · ln(q / min) / ln(max / min)` flow units; when
/// `max == min` every wet segment is at 8.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct FlowUnits {
    /// Smallest flow of a wet vadose segment (network units).
    pub min: f64,
    /// Largest flow of a wet vadose segment (network units).
    pub max: f64,
}

/// The water of one conduit.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct ConduitWater {
    /// Largest flow of its segments, network units.
    pub flow: f64,
    /// Water runs from `nodes[0]` towards the last node in its first segment.
    pub downstream: bool,
    /// No segment carries water (dead end, relict or no route).
    pub dry: bool,
    /// Radius at each node sized from the flow (`hydro.flow_radius`), metres; absent when the
    /// skeleton's radii stand.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub radius: Option<Vec<f64>>,
    /// One entry per segment `nodes[i] → nodes[i + 1]`.
    pub segments: Vec<SegmentWater>,
}

/// The water of one segment of a conduit.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct SegmentWater {
    /// Water runs from `nodes[i]` to `nodes[i + 1]` (false: the other way, or dry).
    pub downstream: bool,
    /// Flow, network units (sink weights or m² of catchment); 0 when dry.
    pub flow: f64,
    /// Flow in m³/s (`hydro.total_discharge` shared in proportion).
    pub discharge: f64,
    /// Water type.
    pub water: WaterType,
    /// Inclination of the segment, radians in [0, π/2].
    pub slope: f64,
    /// Flow in the paper's flow units (see [`FlowUnits`]); 0 when not a running-water type.
    pub flow_units: f64,
    /// Foam, rocks, disturbance and particles of the water type (Table 1).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub look: Option<Look>,
    /// Mean speed, m/s.
    pub speed: f64,
    /// Water depth above the conduit floor (free fall: jet thickness), metres.
    pub depth: f64,
    /// Width of the free surface (free fall: jet width), metres; 0 when full or dry.
    pub width: f64,
    /// Elevation of the water surface at `nodes[i]` and `nodes[i + 1]`, metres; absent when
    /// dry or in free fall.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub level: Option<[f64; 2]>,
    /// The parabola of a free fall.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub fall: Option<Fall>,
}

/// A free fall: the water leaves `lip` horizontally along `direction` at `speed` and follows
/// z = lip.z − g s² / (2 speed²) at horizontal distance s, until it has dropped `drop`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Fall {
    pub lip: [f64; 3],
    /// Unit horizontal direction `[dx, dy]`.
    pub direction: [f64; 2],
    /// Horizontal speed at the lip, m/s.
    pub speed: f64,
    /// Height of the fall, metres.
    pub drop: f64,
    /// Horizontal distance covered during the fall, metres.
    pub throw: f64,
    /// Where the water lands.
    pub impact: [f64; 3],
}

/// A node of the hydraulic graph (Emilien et al. 2015 §4.2).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Role {
    /// A sink: water enters.
    Source,
    /// A spring: water leaves.
    Well,
    /// Water passes or branches.
    Branch,
    /// Water collects: chamber, ponded low point, water table, foot of a free fall.
    Pool,
    /// No water reaches the node.
    Dry,
}

/// The water at one node.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct NodeWater {
    pub role: Role,
    /// Water arriving at the node (recharge included), network units.
    pub inflow: f64,
}

/// The part of a flow that comes from, or goes to, one named key point.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Share {
    pub name: String,
    pub flow: f64,
}

/// A sink and where its water goes.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Sink {
    pub name: String,
    pub node: u32,
    /// Recharge, network units.
    pub recharge: f64,
    /// How its recharge reaches the springs.
    pub springs: Vec<Share>,
}

/// A spring and where its water comes from.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Spring {
    pub name: String,
    pub node: u32,
    /// Discharge, network units.
    pub flow: f64,
    /// The sinks feeding it and how much each gives.
    pub sinks: Vec<Share>,
}
