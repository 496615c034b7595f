//! The samples artifact.

use serde::{Deserialize, Serialize};

use karst_artifact::{Kind, Payload};

/// What a sample stands for.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
pub enum Tag {
    /// A sample of the rock volume.
    Volume,
    /// The key point with this index in the scene's `keypoints`.
    KeyPoint(u32),
}

/// The point cloud through which conduits can run.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Samples {
    /// Positions `[x, y, z]`, metres. Key points come first, in scene order.
    pub positions: Vec<[f64; 3]>,
    /// One tag per position.
    pub tags: Vec<Tag>,
    /// The Poisson-disk radius used, metres.
    pub radius: f64,
}

impl Payload for Samples {
    const KIND: Kind = Kind::Samples;
    const SCHEMA: u32 = 1;
}

impl Samples {
    pub fn len(&self) -> usize {
        self.positions.len()
    }

    pub fn is_empty(&self) -> bool {
        self.positions.is_empty()
    }

    /// Sample index of the scene's key point `keypoint` (key points come first).
    pub fn keypoint_sample(&self, keypoint: usize) -> Option<usize> {
        (self.tags.get(keypoint) == Some(&Tag::KeyPoint(keypoint as u32))).then_some(keypoint)
    }

    /// Number of samples per tag class: (volume, key points).
    pub fn tag_counts(&self) -> (usize, usize) {
        let keypoints = self.tags.iter().filter(|t| matches!(t, Tag::KeyPoint(_))).count();
        (self.len() - keypoints, keypoints)
    }
}
