//! The samples artifact.

use serde::{Deserialize, Serialize};

use karst_artifact::check::{self, MAX_COORDINATE, ensure};
use karst_artifact::{Invalid, Payload, StageId};
use rayon::prelude::*;

use crate::spacing::SpacingField;

/// What a sample stands for.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
pub enum Tag {
    /// A sample of the rock volume.
    Volume,
    /// A sample on the scene's horizon with this index.
    Horizon(u32),
    /// A sample on the scene's water table with this index.
    WaterTable(u32),
    /// A sample on the scene's fault with this index.
    Fault(u32),
    /// The key point with this index in the scene's `keypoints`.
    KeyPoint(u32),
}

/// Number of samples of each tag class.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct TagCounts {
    pub volume: usize,
    pub horizon: usize,
    pub water_table: usize,
    pub fault: usize,
    pub keypoint: usize,
}

/// The point cloud through which conduits can run.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Samples {
    /// Positions `[x, y, z]`, metres. Key points come first, in scene order, then every other
    /// sample (on the surfaces or in the volume: see `tags`) along a Morton curve through the
    /// domain, so that neighbours in space are mostly neighbours in the arrays.
    pub positions: Vec<[f64; 3]>,
    /// One tag per position.
    pub tags: Vec<Tag>,
    /// The smallest Poisson-disk radius of the field, metres.
    pub radius: f64,
    /// The radius field used: two samples p, q (not both key points) are at least
    /// min(r(p), r(q)) apart.
    pub radius_field: SpacingField,
}

impl Payload for Samples {
    const STAGE: StageId = StageId::Sampling;
    const SCHEMA: u32 = 4;

    /// One tag per position, finite positions, no two alike (an edge between them would have no
    /// direction), key point `i` at index `i`, a usable radius field.
    fn validate(&self) -> Result<(), Invalid> {
        ensure(!self.positions.is_empty(), || "positions".into(), || "holds no sample".into())?;
        check::count(|| "tags".into(), self.tags.len(), self.positions.len())?;
        for (i, p) in self.positions.iter().enumerate() {
            check::position(|| format!("positions[{i}]"), p)?;
        }
        for (i, tag) in self.tags.iter().enumerate() {
            if let Tag::KeyPoint(k) = tag {
                ensure(
                    *k as usize == i,
                    || format!("tags[{i}]"),
                    || format!("key point {k} is not sample {k}"),
                )?;
            }
        }
        if let Some((a, b)) = coincident(&self.positions) {
            return Err(Invalid::new(
                format!("positions[{b}]"),
                format!("{:?} is also the position of sample {a}", self.positions[b]),
            ));
        }
        check::positive(|| "radius".into(), self.radius, MAX_COORDINATE)?;
        self.radius_field.validate()
    }
}

/// Two samples at the same position, (smaller index, larger index), if any.
fn coincident(positions: &[[f64; 3]]) -> Option<(usize, usize)> {
    let key = |i: u32| positions[i as usize].map(|c| (c + 0.0).to_bits());
    let mut order: Vec<u32> = (0..positions.len() as u32).collect();
    order.par_sort_unstable_by_key(|&i| (key(i), i));
    order.windows(2).find(|w| key(w[0]) == key(w[1])).map(|w| (w[0] as usize, w[1] as usize))
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

    /// Number of samples per tag class.
    pub fn tag_counts(&self) -> TagCounts {
        let mut c = TagCounts::default();
        for t in &self.tags {
            match t {
                Tag::Volume => c.volume += 1,
                Tag::Horizon(_) => c.horizon += 1,
                Tag::WaterTable(_) => c.water_table += 1,
                Tag::Fault(_) => c.fault += 1,
                Tag::KeyPoint(_) => c.keypoint += 1,
            }
        }
        c
    }
}
