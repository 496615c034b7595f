//! `streams.json`: the surface waterfall network (docs/streams.md).
//!
//! The hydraulic graph of Emilien et al. 2015 §4.2 at the resolution of the waterfall network
//! of §5.2: every trajectory point is a node, every step between two points a segment. Nodes
//! carry the water entering there (a spring's discharge, a curve's own flow, the surface
//! catchment joining the stream); segments carry their flow, Table 1 type, slope, speed, width,
//! depth and rendering attributes; free falls carry their parabola; pools their level and shape.
//! Every flow is in m³/s.

use serde::{Deserialize, Serialize};

use karst_hydro::water::{Look, WaterType};

/// The surface network.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Streams {
    /// Discharges mapped to flow units 1 and 8 (`streams.flow_range`).
    pub flow_range: [f64; 2],
    pub nodes: Vec<Node>,
    pub segments: Vec<Segment>,
    pub pools: Vec<Pool>,
    pub springs: Vec<SpringMouth>,
    /// What the stage corrected or could not do: lowered control points, lakes, springs that
    /// reach daylight outside the domain, implausible types.
    pub reports: Vec<String>,
}

/// What happens to water at a node.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Role {
    /// A spring's mouth or the first point of a curve with its own flow.
    Source,
    /// Water leaves the network: the domain's edge.
    Well,
    /// Water passes (one in, one out), joins or splits.
    Branch,
    /// A pool or lake: its inflow is split equally among its outlets.
    Pool,
}

/// A node of the hydraulic graph.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Node {
    /// On the water surface, metres.
    pub position: [f64; 3],
    pub role: Role,
    /// Water entering here from a spring or a curve's own flow, m³/s.
    pub source: f64,
    /// Surface catchment joining the stream here, m³/s.
    pub lateral: f64,
    /// All the water reaching the node, m³/s.
    pub inflow: f64,
}

/// How water moves along a segment.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Motion {
    /// In contact with the ground.
    Contact,
    /// In the air, along [`Segment::fall`].
    FreeFall,
    /// Across a pool to its outlet (the pool's water body holds it).
    Pool,
}

/// One segment `from → to`, water running downstream.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Segment {
    pub from: u32,
    pub to: u32,
    pub motion: Motion,
    /// The controller curve it follows, if any.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub curve: Option<String>,
    /// m³/s.
    pub flow: f64,
    /// Table 1 type (pool: across a pool; dry: no water).
    pub water: WaterType,
    /// Inclination, radians in [0, π/2] (a fall: of its chord).
    pub slope: f64,
    /// The flow in the paper's flow units.
    pub flow_units: f64,
    /// Foam, rocks, disturbance and particles of the type (Table 1).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub look: Option<Look>,
    /// Mean speed δ, m/s.
    pub speed: f64,
    /// Width ε of the water surface (a fall: of the sheet), metres.
    pub width: f64,
    /// Depth ζ of the water (a fall: thickness of the sheet), metres.
    pub depth: f64,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub fall: Option<Fall>,
}

/// A free fall: from `lip` the water moves along `direction` at horizontal speed `speed` with
/// vertical speed `vertical` (negative: downwards), so z(s) = lip.z + (vertical/speed)·s −
/// g s²/(2 speed²) at horizontal distance s, until `impact`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Fall {
    pub lip: [f64; 3],
    pub direction: [f64; 2],
    pub speed: f64,
    pub vertical: f64,
    pub drop: f64,
    pub throw: f64,
    pub impact: [f64; 3],
}

impl Fall {
    /// The point of the parabola at horizontal distance `s` from the lip.
    pub fn at(&self, s: f64) -> [f64; 3] {
        let [x, y, z] = self.lip;
        let v = self.speed.max(1e-9);
        let dz = self.vertical / v * s - karst_hydro::geometry::G * s * s / (2.0 * v * v);
        [x + self.direction[0] * s, y + self.direction[1] * s, z + dz]
    }
}

/// What made a pool.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum PoolKind {
    /// Dug by a free fall at its foot.
    Plunge,
    /// A hollow of the terrain, filled to its spill point.
    Basin,
    /// A hollow larger than `streams.lake_area`.
    Lake,
    /// A pool controller curve.
    Curve,
}

/// The horizontal extent of a pool.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Outline {
    Disc {
        centre: [f64; 2],
        radius: f64,
    },
    /// Flooded cells, merged into rectangles `[x0, y0, x1, y1]` along rows.
    Cells {
        rectangles: Vec<[f64; 4]>,
    },
    /// A closed polygon, counter-clockwise or not.
    Polygon {
        points: Vec<[f64; 2]>,
    },
}

/// A pool or lake.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Pool {
    pub node: u32,
    pub kind: PoolKind,
    /// Water surface elevation, metres.
    pub level: f64,
    /// Water surface area, m².
    pub area: f64,
    /// Deepest water (plunge: the scour depth dug below `level`), metres.
    pub depth: f64,
    pub outline: Outline,
    /// Where the water leaves, when it does.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub outlet: Option<[f64; 3]>,
    /// The free fall landing in it, for the overhang behind it.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub fall: Option<u32>,
}

/// A spring and where its water reaches daylight.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct SpringMouth {
    pub name: String,
    /// The key point (the conduit's end).
    pub position: [f64; 3],
    /// Where the water comes out on the terrain; absent when that is outside the domain.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub mouth: Option<[f64; 3]>,
    /// Its node in the network.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub node: Option<u32>,
    /// m³/s (the hydro stage's spring flow, scaled by `hydro.total_discharge`).
    pub discharge: f64,
}

impl Streams {
    /// Total length of the segments of each water type, metres, in [`WaterType::ALL`] order.
    pub fn lengths(&self) -> Vec<(WaterType, f64)> {
        WaterType::ALL
            .iter()
            .map(|&w| {
                let length =
                    self.segments.iter().filter(|s| s.water == w).map(|s| self.length(s)).sum::<f64>();
                (w, length)
            })
            .filter(|(_, l)| *l > 0.0)
            .collect()
    }

    /// Length of a segment (a fall: of its chord), metres.
    pub fn length(&self, s: &Segment) -> f64 {
        let [a, b] = [s.from, s.to].map(|n| glam::DVec3::from_array(self.nodes[n as usize].position));
        a.distance(b)
    }

    /// Number of free falls.
    pub fn falls(&self) -> usize {
        self.segments.iter().filter(|s| s.motion == Motion::FreeFall).count()
    }

    /// One line for the pipeline's table.
    pub fn headline(&self) -> String {
        let length =
            self.segments.iter().filter(|s| s.motion == Motion::Contact).map(|s| self.length(s)).sum::<f64>()
                + 0.0;
        let lakes = self.pools.iter().filter(|p| p.kind == PoolKind::Lake).count();
        let out: f64 =
            self.nodes.iter().filter(|n| n.role == Role::Well).map(|n| n.inflow).sum::<f64>() + 0.0;
        format!(
            "{} segments ({length:.0} m running), {} falls, {} pools ({lakes} lakes), {out:.3} m³/s leaving, {} report(s)",
            self.segments.len(),
            self.falls(),
            self.pools.len(),
            self.reports.len()
        )
    }
}
