//! `[sampling]`: adaptive Poisson-disk sampling of the bedrock (Paris et al. 2021 §4.1,
//! KarstNSim §1.1 variable density). The radius field is small on and near the horizons, water
//! tables and faults (`surface_radius` within `surface_distance`), takes each layer's radius in
//! its layer (`radius` elsewhere), and shrinks in karstifiable rock by `potential_factor`.

use serde::{Deserialize, Serialize};

use crate::validate::Checks;

/// Unit of the radii and distances of `[sampling]` and of `geology.layers[].radius`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum RadiusUnit {
    /// Metres.
    #[default]
    Metres,
    /// Fractions of the domain's largest extent.
    Domain,
}

#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct SamplingParams {
    /// Minimum distance between two samples in the volume, far from surfaces. Absent: derived
    /// from the bedrock's volume ([`crate::defaults::sampling_radius_for`]).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub radius: Option<f64>,
    /// Radius on and near horizons, water tables and faults; default `radius`.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub surface_radius: Option<f64>,
    /// Distance over which the radius grows from `surface_radius` to the volume's; default
    /// 2 × `radius`.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub surface_distance: Option<f64>,
    /// Factor on the volume radius where the potential is 1 (linear in the potential); in
    /// (0, 1], default 1 (no effect).
    pub potential_factor: f64,
    /// Consecutive failed darts after which a grid cell is considered full.
    pub attempts: u32,
    /// Unit of the radii and distances.
    pub units: RadiusUnit,
}

impl Default for SamplingParams {
    fn default() -> Self {
        SamplingParams {
            radius: None,
            surface_radius: None,
            surface_distance: None,
            potential_factor: 1.0,
            attempts: 8,
            units: RadiusUnit::Metres,
        }
    }
}

/// Most consecutive failed darts per cell.
pub const MAX_ATTEMPTS: u32 = 1000;

impl SamplingParams {
    pub(crate) fn check(&self, c: &mut Checks) {
        if let Some(r) = self.radius {
            c.positive("sampling.radius", r);
        }
        if let Some(r) = self.surface_radius {
            c.positive("sampling.surface_radius", r);
        }
        if let Some(d) = self.surface_distance {
            c.positive("sampling.surface_distance", d);
        }
        let f = self.potential_factor;
        if c.finite("sampling.potential_factor", &[f]) && !(f > 0.0 && f <= 1.0) {
            c.report("sampling.potential_factor", format!("must be in (0, 1], got {f}"));
        }
        if !(1..=MAX_ATTEMPTS).contains(&self.attempts) {
            c.report("sampling.attempts", format!("must be in [1, {MAX_ATTEMPTS}], got {}", self.attempts));
        }
    }
}
