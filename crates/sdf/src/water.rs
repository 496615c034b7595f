//! The water level of a conduit segment, from what hydro.json gives today (flow and the dry
//! flag per conduit) and the zones of the segment's nodes. This is the one place to switch to
//! a water depth computed by the hydro stage.
//!
//! - a dry conduit holds no water;
//! - a segment whose two nodes are phreatic (below the water table) is flooded: a sump;
//! - vertical shafts (epikarst, deep tubes) drain: water falls through them;
//! - other wet segments carry a stream on their floor, of depth a fraction of the conduit's
//!   height that grows as the square root of the flow (relative to the largest flow of the
//!   network), up to a quarter of the height: a stand-in for the hydraulic depth.

use karst_skeleton::{ConduitType, Zone};

/// What a segment's water looks like.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Water {
    None,
    Flooded,
    /// A stream whose surface lies `depth` metres above the floor.
    Stream {
        depth: f64,
    },
}

/// The inputs of [`level`] for one segment.
#[derive(Debug, Clone, Copy)]
pub struct Segment {
    pub kind: ConduitType,
    pub zones: [Zone; 2],
    pub dry: bool,
    pub flow: f64,
    pub max_flow: f64,
    /// Height of the conduit, metres.
    pub height: f64,
}

/// The water of a segment.
pub fn level(s: &Segment) -> Water {
    if s.dry {
        return Water::None;
    }
    if s.zones == [Zone::Phreatic, Zone::Phreatic] {
        return Water::Flooded;
    }
    if matches!(s.kind, ConduitType::Epikarst | ConduitType::Tube) {
        return Water::None;
    }
    let share = if s.max_flow > 0.0 { (s.flow / s.max_flow).clamp(0.0, 1.0) } else { 0.0 };
    Water::Stream { depth: 0.25 * s.height * share.sqrt() }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn segment(kind: ConduitType, zones: [Zone; 2], flow: f64) -> Segment {
        Segment { kind, zones, dry: flow == 0.0, flow, max_flow: 4.0, height: 2.0 }
    }

    #[test]
    fn sumps_streams_and_shafts() {
        let (v, p) = (Zone::Vadose, Zone::Phreatic);
        assert_eq!(level(&segment(ConduitType::Bed, [p, p], 1.0)), Water::Flooded);
        assert_eq!(level(&segment(ConduitType::Canyon, [v, v], 4.0)), Water::Stream { depth: 0.5 });
        assert_eq!(level(&segment(ConduitType::Canyon, [v, v], 1.0)), Water::Stream { depth: 0.25 });
        assert_eq!(level(&segment(ConduitType::Epikarst, [v, v], 1.0)), Water::None);
        assert_eq!(level(&segment(ConduitType::Bed, [p, p], 0.0)), Water::None);
    }
}
