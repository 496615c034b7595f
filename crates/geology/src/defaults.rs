//! Defaults derived from the scene (issue 38): what depends on the scene's size is computed from
//! it, not fixed in metres, so that a 300 m scene and a 10 km one both come out cave-like.
//! docs/skeleton.md ("Defaults from the scene") gives each rule and its reason.

/// Samples the default sampling radius aims at in the bedrock: enough for the network's
/// passages to bend and branch between the key points at every scale (docs/skeleton.md), few
/// enough for the network half to take seconds on a laptop.
pub const TARGET_SAMPLES: f64 = 30_000.0;

/// Samples per cubic radius of a maximal Poisson-disk set (random close packing of spheres of
/// diameter r; karst-sampling's `PACKING`).
const PACKING: f64 = 0.725;

/// The sampling radius that puts about [`TARGET_SAMPLES`] samples into `bedrock` cubic metres.
pub fn sampling_radius_for(bedrock: f64) -> f64 {
    (PACKING * bedrock.max(1.0) / TARGET_SAMPLES).cbrt()
}
