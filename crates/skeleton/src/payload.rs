//! The skeleton artifact: nodes, conduits and the route of every sink.

use serde::{Deserialize, Serialize};

use karst_artifact::check::{self, MAX_COORDINATE, ensure};
use karst_artifact::{Invalid, Payload, StageId};

/// The type of a conduit segment.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum ConduitType {
    Epikarst,
    Tube,
    Canyon,
    Keyhole,
    Passage,
    Bed,
    Chamber,
}

impl ConduitType {
    /// Every type, in a fixed order.
    pub const ALL: [ConduitType; 7] = [
        ConduitType::Epikarst,
        ConduitType::Tube,
        ConduitType::Canyon,
        ConduitType::Keyhole,
        ConduitType::Passage,
        ConduitType::Bed,
        ConduitType::Chamber,
    ];

    /// Lowercase name, as in the artifact.
    pub fn name(self) -> &'static str {
        match self {
            ConduitType::Epikarst => "epikarst",
            ConduitType::Tube => "tube",
            ConduitType::Canyon => "canyon",
            ConduitType::Keyhole => "keyhole",
            ConduitType::Passage => "passage",
            ConduitType::Bed => "bed",
            ConduitType::Chamber => "chamber",
        }
    }
}

/// Whether a node lies above (vadose) or below (phreatic) the water table.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Zone {
    Vadose,
    Phreatic,
}

/// A node of the network: a sample the conduits pass through.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Node {
    pub position: [f64; 3],
    /// Index of the sample in `samples.bin`.
    pub sample: u32,
    /// Name of the key point at this node, if any.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub keypoint: Option<String>,
    pub zone: Zone,
}

/// A conduit: a chain of nodes between two ends (junctions, dead ends or key points), with the
/// radius of the passage at each node and the type of each segment. A conduit whose ends
/// coincide is a loop. With passage detail (`[sdf] passage_detail`), `profile` gives the
/// passage's size and shape every few metres along it, and `radius` at each node is the
/// profile's there.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Conduit {
    pub nodes: Vec<u32>,
    /// Radius at each node, metres.
    pub radius: Vec<f64>,
    /// Type of each segment (nodes[i] → nodes[i + 1]).
    pub types: Vec<ConduitType>,
    /// The speleogenetic phase that made the conduit (0: the first; later phases keep the
    /// relict conduits of earlier ones).
    #[serde(default)]
    pub phase: u32,
    /// The key points at the conduit's ends, in end order.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub keypoints: Vec<String>,
    /// The passage along the conduit, by increasing arc length from its first node to its
    /// last, with a point at every node (empty without passage detail: the radius at the nodes,
    /// linear in between, and each type's own proportions).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub profile: Vec<ProfilePoint>,
}

impl Conduit {
    /// The index of the profile point at each node, the nodes being at arc lengths `arc`
    /// (empty without a profile): the point nearest each.
    pub fn node_profile_points(&self, arc: &[f64]) -> Vec<usize> {
        if self.profile.is_empty() {
            return Vec::new();
        }
        arc.iter()
            .map(|&a| {
                let k = self.profile.partition_point(|p| p.at < a).min(self.profile.len() - 1);
                if k > 0 && a - self.profile[k - 1].at < self.profile[k].at - a { k - 1 } else { k }
            })
            .collect()
    }

    /// The passage's half-width and ratio (on the type's proportions) at arc length `at`: the
    /// profile's, linear between its points, or without a profile the radius linear between the
    /// nodes at arc lengths `arc`, ratio 1.
    pub fn passage_at(&self, arc: &[f64], at: f64) -> (f64, f64) {
        let lerp = |a: f64, b: f64, t: f64| a + (b - a) * t;
        if self.profile.is_empty() {
            let k = arc.partition_point(|s| *s <= at).clamp(1, arc.len() - 1);
            let t = ((at - arc[k - 1]) / (arc[k] - arc[k - 1])).clamp(0.0, 1.0);
            return (lerp(self.radius[k - 1], self.radius[k], t), 1.0);
        }
        let p = &self.profile;
        let k = p.partition_point(|q| q.at <= at).clamp(1, p.len().max(2) - 1).min(p.len() - 1);
        if k == 0 {
            return (p[0].radius, p[0].ratio);
        }
        let t = ((at - p[k - 1].at) / (p[k].at - p[k - 1].at)).clamp(0.0, 1.0);
        (lerp(p[k - 1].radius, p[k].radius, t), lerp(p[k - 1].ratio, p[k].ratio, t))
    }
}

/// The passage at one point of a conduit's profile.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct ProfilePoint {
    /// Arc length from the conduit's first node, metres.
    pub at: f64,
    /// Half-width of the passage, metres (the conduit radius there).
    pub radius: f64,
    /// Height over width, as a factor on the conduit type's own proportions.
    pub ratio: f64,
}

/// Smallest and largest profile ratio a skeleton may hold.
pub const RATIO_RANGE: [f64; 2] = [1e-3, 1e3];

/// The route water takes from one sink to one spring.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Route {
    pub sink: String,
    pub spring: String,
    /// The sink's weight (its recharge).
    pub weight: f64,
    /// Nodes from sink to spring.
    pub nodes: Vec<u32>,
    /// Cost of the path in the cost graph.
    pub cost: f64,
}

/// The conduit network.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Skeleton {
    pub nodes: Vec<Node>,
    pub conduits: Vec<Conduit>,
    pub routes: Vec<Route>,
    /// The defaults derived from the scene for what it left out (field → resolved value,
    /// `crate::defaults`), so that a run can be reproduced and its hints cite real numbers.
    #[serde(default, skip_serializing_if = "std::collections::BTreeMap::is_empty")]
    pub derived: std::collections::BTreeMap<String, serde_json::Value>,
}

/// Smallest conduit radius a skeleton may hold, metres (the scene's radii are at least 1 mm).
pub const MIN_RADIUS: f64 = 1e-6;
/// Largest route weight (a sink's recharge), far above the scene's limit (docs/limits.md), so
/// that sums of them stay finite.
pub const MAX_WEIGHT: f64 = 1e15;

impl Payload for Skeleton {
    const STAGE: StageId = StageId::Skeleton;
    const SCHEMA: u32 = 3;

    /// At least one conduit; finite node positions; conduits of at least two existing nodes
    /// with one radius (finite, > 0) per node and one type per segment, no segment of length 0;
    /// routes through existing nodes with finite weights and costs ≥ 0.
    fn validate(&self) -> Result<(), Invalid> {
        ensure(
            !self.conduits.is_empty(),
            || "conduits".into(),
            || "is empty: the network has no conduit".into(),
        )?;
        for (i, node) in self.nodes.iter().enumerate() {
            check::position(|| format!("nodes[{i}].position"), &node.position)?;
        }
        for (c, conduit) in self.conduits.iter().enumerate() {
            self.validate_conduit(c, conduit)?;
        }
        for (r, route) in self.routes.iter().enumerate() {
            ensure(!route.nodes.is_empty(), || format!("routes[{r}].nodes"), || "is empty".into())?;
            for (i, &n) in route.nodes.iter().enumerate() {
                check::index(|| format!("routes[{r}].nodes[{i}]"), n as u64, self.nodes.len())?;
            }
            check::within(|| format!("routes[{r}].weight"), route.weight, 0.0, MAX_WEIGHT)?;
            check::within(|| format!("routes[{r}].cost"), route.cost, 0.0, f64::MAX)?;
        }
        Ok(())
    }
}

impl Skeleton {
    fn validate_conduit(&self, c: usize, conduit: &Conduit) -> Result<(), Invalid> {
        let n = conduit.nodes.len();
        ensure(n >= 2, || format!("conduits[{c}].nodes"), || format!("has {n} nodes, a conduit needs 2"))?;
        check::count(|| format!("conduits[{c}].radius"), conduit.radius.len(), n)?;
        check::count(|| format!("conduits[{c}].types"), conduit.types.len(), n - 1)?;
        for (i, &node) in conduit.nodes.iter().enumerate() {
            check::index(|| format!("conduits[{c}].nodes[{i}]"), node as u64, self.nodes.len())?;
        }
        for (i, &r) in conduit.radius.iter().enumerate() {
            check::within(|| format!("conduits[{c}].radius[{i}]"), r, MIN_RADIUS, MAX_COORDINATE)?;
        }
        for (i, w) in conduit.nodes.windows(2).enumerate() {
            let [a, b] = [w[0], w[1]].map(|n| self.nodes[n as usize].position);
            ensure(
                a != b,
                || format!("conduits[{c}].nodes[{}]", i + 1),
                || format!("node {} lies where node {} does: a segment of length 0", w[1], w[0]),
            )?;
        }
        self.validate_profile(c, conduit)
    }

    /// An empty profile, or one that starts at 0, increases strictly and ends at the conduit's
    /// length (to a millimetre), with sizes and ratios in range.
    fn validate_profile(&self, c: usize, conduit: &Conduit) -> Result<(), Invalid> {
        let Some(last) = conduit.profile.last() else { return Ok(()) };
        let length = self.conduit_length(conduit);
        let field = |i: usize, name: &str| format!("conduits[{c}].profile[{i}].{name}");
        for (i, point) in conduit.profile.iter().enumerate() {
            check::within(|| field(i, "radius"), point.radius, MIN_RADIUS, MAX_COORDINATE)?;
            check::within(|| field(i, "ratio"), point.ratio, RATIO_RANGE[0], RATIO_RANGE[1])?;
            check::within(|| field(i, "at"), point.at, 0.0, length + 1e-3)?;
        }
        ensure(
            conduit.profile[0].at == 0.0,
            || field(0, "at"),
            || "must be 0: the conduit's first node".into(),
        )?;
        ensure(
            (last.at - length).abs() <= 1e-3,
            || field(conduit.profile.len() - 1, "at"),
            || format!("is {}, the conduit is {length} m long", last.at),
        )?;
        for (i, w) in conduit.profile.windows(2).enumerate() {
            ensure(w[1].at > w[0].at, || field(i + 1, "at"), || "does not increase".into())?;
        }
        Ok(())
    }

    /// Every link between two nodes, once, as (a, b) with a < b, in conduit order.
    pub fn links(&self) -> Vec<[u32; 2]> {
        self.conduits
            .iter()
            .flat_map(|c| c.nodes.windows(2).map(|w| [w[0].min(w[1]), w[0].max(w[1])]))
            .collect()
    }

    /// Total length of the conduits, metres.
    pub fn total_length(&self) -> f64 {
        self.conduits.iter().map(|c| self.conduit_length(c)).sum()
    }

    /// Length of one conduit, metres.
    pub fn conduit_length(&self, conduit: &Conduit) -> f64 {
        conduit.nodes.windows(2).map(|w| self.segment_length(w[0], w[1])).sum()
    }

    /// The arc length of each node of `conduit` from its first, metres.
    pub fn arc_lengths(&self, conduit: &Conduit) -> Vec<f64> {
        let mut at = vec![0.0];
        for w in conduit.nodes.windows(2) {
            at.push(at[at.len() - 1] + self.segment_length(w[0], w[1]));
        }
        at
    }

    /// Total length of the segments of type `kind`, metres.
    pub fn length_of_type(&self, kind: ConduitType) -> f64 {
        self.conduits
            .iter()
            .flat_map(|c| c.nodes.windows(2).zip(&c.types))
            .filter(|(_, t)| **t == kind)
            .map(|(w, _)| self.segment_length(w[0], w[1]))
            .sum()
    }

    fn segment_length(&self, a: u32, b: u32) -> f64 {
        let [a, b] = [a, b].map(|i| glam::DVec3::from_array(self.nodes[i as usize].position));
        a.distance(b)
    }
}
