//! Gradient-bounded noise for rock irregularities, chamber walls and warps.
//!
//! A fractal sum of plane waves with random directions and phases (a sparse-spectrum gradient
//! noise): n(p) = Σ_o g^o / W · (1/K) Σ_k sin(2^o·ω·(d_k·p) + φ_k). Unlike lattice Perlin noise its
//! gradient bound is exact and simple, which is what keeps the field 1-Lipschitz: every wave has
//! gradient norm at most its amplitude times its angular frequency, so
//! |∇n| ≤ Σ_o g^o 2^o ω / W = [`WaveNoise::gradient_bound`]. Values lie in [−1, 1]
//! (W = Σ_o g^o normalises the amplitudes). Directions and phases are drawn from the scene's
//! random stream, so the noise is part of the deterministic model.

use glam::DVec3;
use karst_scene::rng::Random;
use serde::{Deserialize, Serialize};

/// Waves per octave.
const WAVES: usize = 3;
/// Octaves of the fractal sum.
const OCTAVES: usize = 3;
/// Amplitude ratio between consecutive octaves.
const GAIN: f64 = 0.5;

/// One plane wave of an octave: unit direction and phase.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Wave {
    pub direction: [f32; 3],
    pub phase: f32,
}

/// The noise: `OCTAVES × WAVES` waves at base wavelength `wavelength` metres.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct WaveNoise {
    pub wavelength: f64,
    pub waves: Vec<Wave>,
}

impl WaveNoise {
    /// A noise of base wavelength `wavelength` (metres) drawn from `random`.
    pub fn draw(random: &mut Random, wavelength: f64) -> Self {
        let waves = (0..OCTAVES * WAVES)
            .map(|_| {
                // Uniform direction on the sphere.
                let z = random.range(-1.0, 1.0);
                let a = random.range(0.0, std::f64::consts::TAU);
                let s = (1.0 - z * z).sqrt();
                let direction = [(s * a.cos()) as f32, (s * a.sin()) as f32, z as f32];
                Wave { direction, phase: random.range(0.0, std::f64::consts::TAU) as f32 }
            })
            .collect();
        WaveNoise { wavelength, waves }
    }

    fn omega(&self) -> f64 {
        std::f64::consts::TAU / self.wavelength
    }

    fn weight() -> f64 {
        (0..OCTAVES).map(|o| GAIN.powi(o as i32)).sum()
    }

    /// n(p) ∈ [−1, 1].
    pub fn value(&self, p: DVec3) -> f64 {
        let mut sum = 0.0;
        let mut frequency = self.omega();
        let mut amplitude = 1.0 / (Self::weight() * WAVES as f64);
        for octave in self.waves.chunks(WAVES) {
            for w in octave {
                let d = DVec3::new(w.direction[0] as f64, w.direction[1] as f64, w.direction[2] as f64);
                sum += amplitude * (frequency * d.dot(p) + w.phase as f64).sin();
            }
            frequency *= 2.0;
            amplitude *= GAIN;
        }
        sum
    }

    /// A displacement vector field with components in [−1, 1]: the noise at three offsets.
    /// Each component has gradient norm ≤ `gradient_bound()`, so the Jacobian's spectral norm is
    /// at most √3 times that.
    pub fn vector(&self, p: DVec3) -> DVec3 {
        let shift = self.wavelength * 0.371;
        DVec3::new(
            self.value(p),
            self.value(p + DVec3::new(shift, 0.0, 0.0)),
            self.value(p + DVec3::new(0.0, shift, 0.0)),
        )
    }

    /// Checks a decoded noise: a finite base wavelength > 0 and the `OCTAVES × WAVES` waves
    /// of unit direction its gradient bound (hence the field's 1-Lipschitz bound) assumes.
    pub fn validate(&self, field: &str) -> Result<(), karst_artifact::Invalid> {
        use karst_artifact::check::{self, MAX_COORDINATE};
        check::positive(|| format!("{field}.wavelength"), self.wavelength, MAX_COORDINATE)?;
        check::count(|| format!("{field}.waves"), self.waves.len(), OCTAVES * WAVES)?;
        for (i, w) in self.waves.iter().enumerate() {
            let norm = w.direction.iter().map(|c| (*c as f64).powi(2)).sum::<f64>().sqrt();
            check::within(|| format!("{field}.waves[{i}].direction"), norm, 1.0 - 1e-6, 1.0 + 1e-6)?;
            check::within(|| format!("{field}.waves[{i}].phase"), w.phase as f64, -1e3, 1e3)?;
        }
        Ok(())
    }

    /// Upper bound of |∇n| (direction norms are rounded to f32, hence the small margin).
    pub fn gradient_bound(&self) -> f64 {
        let sum: f64 = (0..OCTAVES).map(|o| (GAIN * 2.0).powi(o as i32)).sum();
        sum * self.omega() / Self::weight() * (1.0 + 1e-6)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::testing::Pairs;

    #[test]
    fn values_and_gradient_are_bounded() {
        let noise = WaveNoise::draw(&mut Random::stream(3, "sdf", "test"), 4.0);
        let g = noise.gradient_bound();
        for (p, q) in Pairs::new(11, 50.0, 2.0).take(20_000) {
            assert!(noise.value(p).abs() <= 1.0);
            assert!((noise.value(p) - noise.value(q)).abs() <= g * p.distance(q) * (1.0 + 1e-9));
        }
    }
}
