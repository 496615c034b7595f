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
    /// direction), key point `i` at index `i`, at least one sample that is not a key point (the
    /// conduits run through those), a usable radius field.
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
        ensure(
            self.tags.iter().any(|t| !matches!(t, Tag::KeyPoint(_))),
            || "tags".into(),
            || {
                format!(
                    "all {} samples are key points: no sample of the rock lies between them (sampling never writes this)",
                    self.tags.len()
                )
            },
        )?;
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

/// Two samples at the same position, if any: the first sample (in file order) whose position
/// an earlier one has, and the first of those earlier ones.
///
/// Each position's bits (−0 read as +0) are hashed to one number, sorted with the sample's index
/// beside it (sorting the indices by their positions looked every position up at each
/// comparison: the largest part of reading a samples artifact), and the positions of equal
/// hashes are compared; a collision of different positions costs a comparison, nothing more.
fn coincident(positions: &[[f64; 3]]) -> Option<(usize, usize)> {
    let bits = |i: usize| positions[i].map(|c| (c + 0.0).to_bits());
    let mut keyed: Vec<u128> = (0..positions.len())
        .into_par_iter()
        .map(|i| u128::from(position_hash(bits(i))) << 32 | i as u128)
        .collect();
    keyed.par_sort_unstable();
    let index = |key: &u128| *key as u32 as usize;
    let mut first: Option<(usize, usize)> = None;
    for run in keyed.chunk_by(|a, b| a >> 32 == b >> 32).filter(|run| run.len() > 1) {
        for (n, later) in run.iter().enumerate().skip(1) {
            let later = index(later);
            let earlier = run[..n].iter().map(index).find(|&a| bits(a) == bits(later));
            if let Some(a) = earlier.filter(|_| first.is_none_or(|(_, b)| later < b)) {
                first = Some((a, later));
            }
        }
    }
    first
}

/// A 64-bit hash of a position's bits (splitmix64's finaliser on each coordinate in turn).
fn position_hash(bits: [u64; 3]) -> u64 {
    let mix = |mut z: u64| {
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    };
    bits.iter().fold(0x9E37_79B9_7F4A_7C15, |h, &b| mix(h ^ b))
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

#[cfg(test)]
mod tests {
    use super::*;

    /// The first sample whose position an earlier one has, by comparing every pair.
    fn brute(positions: &[[f64; 3]]) -> Option<(usize, usize)> {
        let same = |a: &[f64; 3], b: &[f64; 3]| a.iter().zip(b).all(|(x, y)| x == y);
        (0..positions.len())
            .find_map(|b| (0..b).find(|&a| same(&positions[a], &positions[b])).map(|a| (a, b)))
    }

    #[test]
    fn coincident_samples_are_the_first_repeat_in_file_order() {
        let mut rng = karst_scene::rng::Random::stream(7, "test", "coincident");
        let mut next = || rng.index(8) as f64 - 4.0;
        // Coarse coordinates repeat often; the sets grow until repeats appear and beyond.
        for n in [1, 2, 50, 120, 300, 600] {
            let positions: Vec<[f64; 3]> = (0..n).map(|_| [next(), next(), next() * 0.5]).collect();
            assert_eq!(coincident(&positions), brute(&positions), "{n} samples");
        }
        let distinct: Vec<[f64; 3]> = (0..1000).map(|i| [i as f64, (i % 7) as f64, 0.0]).collect();
        assert_eq!(coincident(&distinct), None);
        let signed_zero = [[1.0, 2.0, 3.0], [0.0, 5.0, -0.0], [9.0, 9.0, 9.0], [-0.0, 5.0, 0.0]];
        assert_eq!(coincident(&signed_zero), Some((1, 3)));
    }
}
