//! Rough walls: band-limited relief from decimetres to metres on every conduit wall, its
//! amplitude a fraction of the local passage size (bounded), added to each sweep and sphere
//! leaf beside the per-type detail noise (crate::field::primitive::Context::detail).
//!
//! The relief is a fractal sum of plane waves like [`crate::tree::noise::WaveNoise`], with more
//! octaves: the longest wavelength λ halves four times (4 m reaches 0.25 m), and
//! each octave's amplitude is 0.6 times the one before ([`SPECTRUM`]), a spectrum flatter than Brownian
//! relief so that the decimetre scallops and blades stay visible beside metre-scale alcoves.
//! Values lie in [−1, 1] and the gradient is at most the tight bound over the sign patterns of
//! the waves ([`ReliefNoise::gradient_bound`], below Σ_o g^o 2^o ω / W with ω = 2π/λ and
//! W = Σ_o g^o). A leaf of size s (a sphere's radius, a sweep's extent) gets the amplitude
//! R = min(fraction·s, max); its value, (f + A·n + R·r)/(1 + A·G + R·G_r) clamped to
//! [f − A − R, f + A + R] (crate::field::primitive::Context), stays 1-Lipschitz (docs/sdf.md,
//! "Rough walls").

use glam::DVec3;
use karst_scene::rng::Random;
use serde::{Deserialize, Serialize};

use crate::tree::noise::{Spectrum, Wave};

/// The relief's spectrum: the longest wavelength and four halvings, three waves each, each
/// octave 0.6 times the amplitude of the one before.
const SPECTRUM: Spectrum = Spectrum { octaves: 5, waves: 3, gain: 0.6 };

/// The relief noise: the waves of [`SPECTRUM`], longest wavelength `wavelength` metres.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct ReliefNoise {
    pub wavelength: f64,
    pub waves: Vec<Wave>,
}

/// The rough-wall relief: its noise and how its amplitude follows the passage size.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Relief {
    /// Amplitude as a fraction of the leaf's size.
    pub fraction: f64,
    /// Largest amplitude, metres.
    pub max: f64,
    pub noise: ReliefNoise,
}

impl Relief {
    /// The relief amplitude of a leaf of size `size` metres: min(fraction·size, max).
    pub fn amplitude(&self, size: f64) -> f64 {
        (self.fraction * size).min(self.max)
    }

    /// Checks a decoded relief (what its Lipschitz bound assumes).
    pub fn validate(&self, field: &str) -> Result<(), karst_artifact::Invalid> {
        use karst_artifact::check;
        check::within(|| format!("{field}.fraction"), self.fraction, 0.0, 0.5)?;
        check::within(|| format!("{field}.max"), self.max, 0.0, 10.0)?;
        self.noise.validate(&format!("{field}.noise"))
    }
}

impl ReliefNoise {
    /// A relief of longest wavelength `wavelength` metres drawn from `random`.
    pub fn draw(random: &mut Random, wavelength: f64) -> Self {
        ReliefNoise { wavelength, waves: SPECTRUM.draw(random) }
    }

    /// r(p) ∈ [−1, 1].
    pub fn value(&self, p: DVec3) -> f64 {
        SPECTRUM.value(&self.waves, self.wavelength, p)
    }

    /// Upper bound of |∇r|: the tight bound of its drawn waves
    /// ([`Spectrum::gradient_bound_of`]), on average about two thirds of the sum of the
    /// waves' own bounds.
    pub fn gradient_bound(&self) -> f64 {
        SPECTRUM.gradient_bound_of(&self.waves, self.wavelength)
    }

    fn validate(&self, field: &str) -> Result<(), karst_artifact::Invalid> {
        karst_artifact::check::within(|| format!("{field}.wavelength"), self.wavelength, 0.1, 100.0)?;
        SPECTRUM.validate(field, &self.waves)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::testing::Pairs;

    #[test]
    fn values_and_gradient_are_bounded() {
        let noise = ReliefNoise::draw(&mut Random::stream(5, "sdf", "test"), 4.0);
        let g = noise.gradient_bound();
        let mut steepest: f64 = 0.0;
        for (p, q) in Pairs::new(13, 30.0, 0.3).take(20_000) {
            assert!(noise.value(p).abs() <= 1.0);
            let slope = (noise.value(p) - noise.value(q)).abs() / p.distance(q);
            assert!(slope <= g * (1.0 + 1e-9), "{slope} > {g}");
            steepest = steepest.max(slope);
        }
        // The bound is not vacuous: the finest octaves are steep.
        assert!(steepest > 0.25 * g, "{steepest} vs {g}");
    }

    #[test]
    fn the_amplitude_follows_the_size_up_to_its_bound() {
        let relief = Relief {
            fraction: 0.1,
            max: 0.5,
            noise: ReliefNoise::draw(&mut Random::stream(1, "a", "b"), 4.0),
        };
        assert_eq!(relief.amplitude(2.0), 0.2);
        assert_eq!(relief.amplitude(50.0), 0.5);
    }
}
