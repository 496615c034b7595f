//! Defaults derived from the scene (issue 38): what depends on the scene's size is computed from
//! it, not fixed in metres, so that a 300 m scene and a 10 km one both come out cave-like.
//! docs/skeleton.md ("Defaults from the scene") gives each rule and its reason.
//!
//! Here: the sampling radius when `[sampling]` leaves it out, which the sampling stage samples
//! with and the skeleton scales its tributaries and meanders by.

use crate::params::{RadiusUnit, SamplingParams};
use karst_geology::{Domain, Terrain};

/// Samples the default sampling radius aims at in the bedrock: enough for the passages to bend
/// and branch between the key points, few enough for the network half to take seconds.
pub const TARGET_SAMPLES: f64 = 30_000.0;

/// The largest default sampling radius, metres. No branch is shorter than twice the radius and
/// junctions are a few radii apart along a passage, so the radius bounds the mean branch length
/// from below; real caves' mean branch length is at most 332 m (Collon et al. 2017) and mostly
/// 10–80 m (KNdata-public), so large scenes get more samples than [`TARGET_SAMPLES`] instead of
/// branches longer than any cave's.
pub const MAX_DEFAULT_RADIUS: f64 = 50.0;

/// Samples per cubic radius of a maximal Poisson-disk set (random close packing of spheres of
/// diameter r; karst-sampling's `PACKING`).
const PACKING: f64 = 0.725;

/// Columns of the grid the bedrock's volume is measured on, per side.
const VOLUME_GRID: usize = 64;

/// The sampling radius that puts about [`TARGET_SAMPLES`] samples into `bedrock` cubic metres,
/// at most [`MAX_DEFAULT_RADIUS`].
pub fn sampling_radius_for(bedrock: f64) -> f64 {
    (PACKING * bedrock.max(1.0) / TARGET_SAMPLES).cbrt().min(MAX_DEFAULT_RADIUS)
}

/// The bedrock's volume, cubic metres: the domain below the terrain, measured on a
/// [`VOLUME_GRID`]² grid of columns.
pub fn bedrock_volume(domain: &Domain, terrain: &Terrain) -> f64 {
    let (lo, hi) = (domain.min(), domain.max());
    let size = domain.size();
    let n = VOLUME_GRID;
    let column = |i: usize, j: usize| {
        let x = lo.x + (i as f64 + 0.5) / n as f64 * size.x;
        let y = lo.y + (j as f64 + 0.5) / n as f64 * size.y;
        (terrain.height(x, y).min(hi.z) - lo.z).max(0.0)
    };
    let sum: f64 = (0..n).flat_map(|i| (0..n).map(move |j| (i, j))).map(|(i, j)| column(i, j)).sum();
    sum * size.x * size.y / (n * n) as f64
}

impl SamplingParams {
    /// The volume radius in metres: `radius` (times the domain's largest extent with
    /// `units = "domain"`), or, left out, [`sampling_radius_for`] the bedrock's volume.
    pub fn radius_metres(&self, domain: &Domain, terrain: &Terrain) -> f64 {
        match self.radius {
            Some(r) => r * self.unit_scale(domain),
            None => sampling_radius_for(bedrock_volume(domain, terrain)),
        }
    }

    /// Metres per unit of the radii and distances of `[sampling]`.
    pub fn unit_scale(&self, domain: &Domain) -> f64 {
        match self.units {
            RadiusUnit::Metres => 1.0,
            RadiusUnit::Domain => domain.size().max_element(),
        }
    }

    /// The volume radius in the section's units: `radius`, or the derived default converted.
    pub fn radius_in_units(&self, domain: &Domain, terrain: &Terrain) -> f64 {
        self.radius_metres(domain, terrain) / self.unit_scale(domain)
    }
}
