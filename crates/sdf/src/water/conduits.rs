//! The water level of a conduit segment, from the hydro stage's water of that segment
//! (Emilien et al. 2015 types, free-surface depth) and the zones of its nodes:
//!
//! - dry segments hold no water;
//! - sumps (flooded, phreatic) and pools fill the conduit: flooded;
//! - free falls (ribbon, plunge, ledge, cataract) and shafts let the water fall through: no
//!   standing water is modelled in them;
//! - other running water (stream, river, rapid, cascade, horsetail, block) is a stream on the
//!   conduit's floor, as deep as the hydro stage computed, at most the conduit's height.

use karst_hydro::WaterType;
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
    /// The hydro stage's water type of the segment.
    pub water: WaterType,
    /// The hydro stage's free-surface depth, metres.
    pub depth: f64,
    /// Height of the conduit, metres.
    pub height: f64,
}

/// The water of a segment.
pub fn level(s: &Segment) -> Water {
    use WaterType::*;
    match s.water {
        Dry => Water::None,
        Sump | Pool => Water::Flooded,
        Ribbon | Plunge | Ledge | Cataract => Water::None,
        _ if matches!(s.kind, ConduitType::Epikarst | ConduitType::Tube) => Water::None,
        _ if s.zones == [Zone::Phreatic, Zone::Phreatic] => Water::Flooded,
        _ => Water::Stream { depth: s.depth.clamp(0.0, s.height) },
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn segment(kind: ConduitType, zones: [Zone; 2], water: WaterType, depth: f64) -> Segment {
        Segment { kind, zones, water, depth, height: 2.0 }
    }

    #[test]
    fn sumps_streams_falls_and_shafts() {
        let (v, p) = (Zone::Vadose, Zone::Phreatic);
        assert_eq!(level(&segment(ConduitType::Bed, [p, p], WaterType::Sump, 0.3)), Water::Flooded);
        assert_eq!(
            level(&segment(ConduitType::Canyon, [v, v], WaterType::Stream, 0.5)),
            Water::Stream { depth: 0.5 }
        );
        assert_eq!(
            level(&segment(ConduitType::Canyon, [v, v], WaterType::River, 9.0)),
            Water::Stream { depth: 2.0 }
        );
        assert_eq!(level(&segment(ConduitType::Passage, [v, v], WaterType::Ledge, 0.2)), Water::None);
        assert_eq!(level(&segment(ConduitType::Epikarst, [v, v], WaterType::Rapid, 0.1)), Water::None);
        assert_eq!(level(&segment(ConduitType::Bed, [p, p], WaterType::Dry, 0.0)), Water::None);
    }
}
