//! Where an artifact's coordinates lie in the world: the origin of the scene's local frame and
//! its coordinate reference system.
//!
//! Stages compute in local coordinates (world − origin, the origin being the domain's `min`
//! corner), so that the f32 vertices of meshes keep sub-millimetre precision at the
//! coordinates of a projected CRS (y ≈ 6.9e6 m in Lambert-93, where an f32 resolves 0.5 m).
//! Every artifact header records the frame; exports and viewers add the origin back.

use serde::{Deserialize, Serialize};

/// The local frame of a run.
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
pub struct Frame {
    /// World coordinates of the local origin, metres (f64: exact for any coordinate on Earth).
    pub origin: [f64; 3],
    /// The scene's coordinate reference system (`"EPSG:2154"`), if it names one.
    pub crs: Option<String>,
}

impl Frame {
    /// The world coordinates of a local point.
    #[inline]
    pub fn world(&self, local: [f64; 3]) -> [f64; 3] {
        std::array::from_fn(|a| local[a] + self.origin[a])
    }

    /// The frame as text for artifact keys: two runs in different frames never share a key.
    pub fn key_text(&self) -> String {
        serde_json::to_string(self).expect("a frame always serializes")
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn world_adds_the_origin_exactly() {
        let frame = Frame { origin: [651000.0, 6862000.0, 250.0], crs: Some("EPSG:2154".into()) };
        assert_eq!(frame.world([234.567, 345.678, 1.5]), [651234.567, 6862345.678, 251.5]);
        assert_ne!(frame.key_text(), Frame::default().key_text());
    }
}
