//! `streams.json`: the surface waterfall network (docs/streams.md).
//!
//! The hydraulic graph of Emilien et al. 2015 §4.2 at the resolution of the waterfall network
//! of §5.2: every trajectory point is a node, every step between two points a segment. Nodes
//! carry the water entering there (a spring's discharge, a curve's own flow, the surface
//! catchment joining the stream); segments carry their flow, Table 1 type, slope, speed, width,
//! depth and rendering attributes; free falls carry their parabola; pools their level and shape.
//! Every flow is in m³/s. [`Payload::validate`] checks every index and number on reading, so
//! the sdf and metrics stages can use a streams.json that passes without further checks.

use glam::DVec3;
use serde::{Deserialize, Serialize};

use karst_artifact::{Invalid, Payload, StageId};
use karst_hydro::{Look, WaterType};

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

impl Payload for Streams {
    const STAGE: StageId = StageId::Streams;
    const SCHEMA: u32 = 1;

    fn validate(&self) -> Result<(), Invalid> {
        let [lo, hi] = self.flow_range;
        if !(lo > 0.0 && hi > lo && hi.is_finite()) {
            return Err(Invalid::new(
                "flow_range",
                format!("{:?} is not a range of positive flows", self.flow_range),
            ));
        }
        for (i, n) in self.nodes.iter().enumerate() {
            finite(&format!("nodes[{i}].position"), &n.position)?;
            for (field, value) in [("source", n.source), ("lateral", n.lateral), ("inflow", n.inflow)] {
                flow(&format!("nodes[{i}].{field}"), value)?;
            }
        }
        for (i, s) in self.segments.iter().enumerate() {
            self.node(&format!("segments[{i}].from"), s.from)?;
            self.node(&format!("segments[{i}].to"), s.to)?;
            for (field, value) in [
                ("flow", s.flow),
                ("flow_units", s.flow_units),
                ("speed", s.speed),
                ("width", s.width),
                ("depth", s.depth),
            ] {
                flow(&format!("segments[{i}].{field}"), value)?;
            }
            if !(0.0..=std::f64::consts::FRAC_PI_2).contains(&s.slope) {
                return Err(Invalid::new(
                    format!("segments[{i}].slope"),
                    format!("{} is not in [0, π/2]", s.slope),
                ));
            }
            match (&s.fall, s.motion) {
                (Some(f), Motion::FreeFall) => f.validate(&format!("segments[{i}].fall"))?,
                (None, Motion::FreeFall) => {
                    return Err(Invalid::new(
                        format!("segments[{i}].fall"),
                        "a free fall without its parabola",
                    ));
                }
                (Some(_), _) => {
                    return Err(Invalid::new(
                        format!("segments[{i}].fall"),
                        "a parabola on a segment that does not fall",
                    ));
                }
                (None, _) => {}
            }
        }
        for (i, p) in self.pools.iter().enumerate() {
            self.node(&format!("pools[{i}].node"), p.node)?;
            finite(&format!("pools[{i}].level"), &[p.level])?;
            flow(&format!("pools[{i}].area"), p.area)?;
            flow(&format!("pools[{i}].depth"), p.depth)?;
            p.outline.validate(&format!("pools[{i}].outline"))?;
            if let Some(outlet) = &p.outlet {
                finite(&format!("pools[{i}].outlet"), outlet)?;
            }
            if let Some(f) = p.fall
                && self.segments.get(f as usize).is_none_or(|s| s.motion != Motion::FreeFall)
            {
                return Err(Invalid::new(
                    format!("pools[{i}].fall"),
                    format!("segment {f} is not a free fall"),
                ));
            }
        }
        for (i, s) in self.springs.iter().enumerate() {
            finite(&format!("springs[{i}].position"), &s.position)?;
            if let Some(mouth) = &s.mouth {
                finite(&format!("springs[{i}].mouth"), mouth)?;
            }
            if let Some(node) = s.node {
                self.node(&format!("springs[{i}].node"), node)?;
            }
            flow(&format!("springs[{i}].discharge"), s.discharge)?;
        }
        Ok(())
    }
}

impl Streams {
    /// `node` must name a node.
    fn node(&self, field: &str, node: u32) -> Result<(), Invalid> {
        if (node as usize) < self.nodes.len() {
            Ok(())
        } else {
            Err(Invalid::new(field, format!("node {node} does not exist ({} nodes)", self.nodes.len())))
        }
    }
}

/// Every number of `values` must be finite.
fn finite(field: &str, values: &[f64]) -> Result<(), Invalid> {
    match values.iter().find(|v| !v.is_finite()) {
        Some(v) => Err(Invalid::new(field, format!("{v} is not a finite number"))),
        None => Ok(()),
    }
}

/// A flow, area, speed or length: finite and ≥ 0.
fn flow(field: &str, value: f64) -> Result<(), Invalid> {
    if value.is_finite() && value >= 0.0 {
        Ok(())
    } else {
        Err(Invalid::new(field, format!("{value} must be a finite number ≥ 0")))
    }
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
    fn validate(&self, field: &str) -> Result<(), Invalid> {
        finite(field, &[self.lip, self.impact].concat())?;
        finite(field, &[self.direction[0], self.direction[1], self.vertical])?;
        let unit = (self.direction[0].hypot(self.direction[1]) - 1.0).abs() < 1e-6;
        if !(unit && self.speed > 0.0 && self.drop >= 0.0 && self.throw >= 0.0) {
            return Err(Invalid::new(
                field,
                "direction must be a unit vector, speed > 0, drop and throw ≥ 0".to_string(),
            ));
        }
        Ok(())
    }

    /// Length of the parabola from the lip to the impact, metres: with slope u(s) = a − 2bs
    /// (a = vertical/speed, b = g/(2 speed²)), ∫ √(1 + u²) ds = [F(a) − F(a − 2b·throw)]/(2b),
    /// F(u) = (u√(1 + u²) + asinh u)/2.
    pub fn arc_length(&self) -> f64 {
        let v = self.speed.max(1e-9);
        let (a, b) = (self.vertical / v, karst_hydro::G / (2.0 * v * v));
        let f = |u: f64| 0.5 * (u * (1.0 + u * u).sqrt() + u.asinh());
        (f(a) - f(a - 2.0 * b * self.throw)) / (2.0 * b)
    }

    /// The point of the parabola at horizontal distance `s` from the lip.
    pub fn at(&self, s: f64) -> [f64; 3] {
        let [x, y, z] = self.lip;
        let v = self.speed.max(1e-9);
        let dz = self.vertical / v * s - karst_hydro::G * s * s / (2.0 * v * v);
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

impl Outline {
    /// Finite, of positive size: what the carving and the meshes rely on.
    pub fn validate(&self, field: &str) -> Result<(), Invalid> {
        match self {
            Outline::Disc { centre, radius } => {
                finite(field, &[centre[0], centre[1], *radius])?;
                if *radius <= 0.0 {
                    return Err(Invalid::new(field, format!("radius {radius} is not > 0")));
                }
            }
            Outline::Cells { rectangles } => {
                for (k, r) in rectangles.iter().enumerate() {
                    finite(field, r)?;
                    if !(r[0] <= r[2] && r[1] <= r[3]) {
                        return Err(Invalid::new(
                            format!("{field}.rectangles[{k}]"),
                            format!("{r:?} is not x0 ≤ x1, y0 ≤ y1"),
                        ));
                    }
                }
            }
            Outline::Polygon { points } => {
                finite(field, &points.concat())?;
                if points.len() < 3 {
                    return Err(Invalid::new(field, format!("a polygon of {} points", points.len())));
                }
            }
        }
        Ok(())
    }
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

    /// Length of a segment (a fall: along its parabola), metres.
    pub fn length(&self, s: &Segment) -> f64 {
        if let Some(fall) = &s.fall {
            return fall.arc_length();
        }
        let [a, b] = [s.from, s.to].map(|n| DVec3::from_array(self.nodes[n as usize].position));
        a.distance(b)
    }

    /// Number of free falls.
    pub fn falls(&self) -> usize {
        self.segments.iter().filter(|s| s.motion == Motion::FreeFall).count()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn fall(vertical: f64) -> Fall {
        Fall {
            lip: [0.0, 0.0, 30.0],
            direction: [0.6, 0.8],
            speed: 2.5,
            vertical,
            drop: 20.0,
            throw: 4.0,
            impact: [2.4, 3.2, 10.0],
        }
    }

    #[test]
    fn a_fall_s_arc_length_is_the_length_of_its_parabola() {
        for vertical in [0.0, -1.5, 0.8] {
            let f = fall(vertical);
            let n = 100_000;
            let chords: f64 = (0..n)
                .map(|i| {
                    let [a, b] = [i, i + 1].map(|k| DVec3::from_array(f.at(f.throw * k as f64 / n as f64)));
                    a.distance(b)
                })
                .sum();
            assert!((f.arc_length() - chords).abs() < 1e-6 * chords, "{} vs {chords}", f.arc_length());
        }
    }

    fn streams() -> Streams {
        let node = |z: f64| Node {
            position: [0.0, 0.0, z],
            role: Role::Branch,
            source: 0.0,
            lateral: 0.0,
            inflow: 1.0,
        };
        let segment = |motion, fall| Segment {
            from: 0,
            to: 1,
            motion,
            curve: None,
            flow: 1.0,
            water: WaterType::Ribbon,
            slope: 1.5,
            flow_units: 3.0,
            look: None,
            speed: 2.5,
            width: 1.0,
            depth: 0.2,
            fall,
        };
        Streams {
            flow_range: [0.005, 500.0],
            nodes: vec![node(30.0), node(10.0)],
            segments: vec![segment(Motion::FreeFall, Some(fall(0.0))), segment(Motion::Contact, None)],
            pools: vec![Pool {
                node: 1,
                kind: PoolKind::Plunge,
                level: 10.0,
                area: 12.0,
                depth: 1.0,
                outline: Outline::Disc { centre: [2.4, 3.2], radius: 2.0 },
                outlet: None,
                fall: Some(0),
            }],
            springs: Vec::new(),
            reports: Vec::new(),
        }
    }

    #[test]
    fn validate_names_the_wrong_field() {
        assert_eq!(streams().validate(), Ok(()));
        let field = |change: fn(&mut Streams)| {
            let mut s = streams();
            change(&mut s);
            s.validate().unwrap_err().field
        };
        assert_eq!(field(|s| s.segments[1].to = 7), "segments[1].to");
        assert_eq!(field(|s| s.nodes[0].position[2] = f64::NAN), "nodes[0].position");
        assert_eq!(field(|s| s.segments[0].fall = None), "segments[0].fall");
        assert_eq!(field(|s| s.segments[1].fall = Some(fall(0.0))), "segments[1].fall");
        assert_eq!(field(|s| s.segments[1].width = -1.0), "segments[1].width");
        assert_eq!(field(|s| s.segments[1].slope = 2.0), "segments[1].slope");
        assert_eq!(field(|s| s.pools[0].fall = Some(1)), "pools[0].fall");
        assert_eq!(
            field(|s| s.pools[0].outline = Outline::Polygon { points: vec![[0.0, 0.0]] }),
            "pools[0].outline"
        );
        assert_eq!(field(|s| s.flow_range = [5.0, 1.0]), "flow_range");
    }
}
