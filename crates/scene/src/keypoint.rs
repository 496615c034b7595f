//! Key points: the field data the network must honour. Sinks (inlets) are where water enters,
//! springs (outlets) where it leaves, waypoints are known passages the network must visit,
//! dead ends are known blind passages (a breakout chamber, a choke) joined to it once.

use serde::{Deserialize, Serialize};

use karst_geology::Point;

/// What a key point is.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum KeyPointKind {
    Sink,
    Spring,
    Waypoint,
    /// A known blind passage: the network reaches it, nothing flows on from it.
    DeadEnd,
}

/// One key point of the scene (`[[keypoints]]`).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct KeyPoint {
    /// Unique name, used in messages and in the outputs.
    pub name: String,
    pub kind: KeyPointKind,
    /// `[x, y, z]`, inside the domain, at or below the terrain.
    pub position: [f64; 3],
    /// Sinks: relative recharge (default 1); the flow a sink feeds into the network.
    #[serde(default = "one")]
    pub weight: f64,
    /// Sinks: iteration order, smaller first (default 0).
    #[serde(default)]
    pub order: i64,
    /// Springs: name of the water table the spring drains.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub water_table: Option<String>,
}

fn one() -> f64 {
    1.0
}

impl KeyPoint {
    pub fn point(&self) -> Point {
        Point::from_array(self.position)
    }
}

/// The key points of `kind` among `keypoints`, with their index, in scene order.
pub fn keypoints_of(keypoints: &[KeyPoint], kind: KeyPointKind) -> impl Iterator<Item = (usize, &KeyPoint)> {
    keypoints.iter().enumerate().filter(move |(_, k)| k.kind == kind)
}
