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

/// The detail noise's spectrum: three octaves of three waves, each octave half the amplitude of
/// the one before.
const SPECTRUM: Spectrum = Spectrum { octaves: 3, waves: 3, gain: 0.5 };

/// The shape of a fractal sum of plane waves: `octaves` octaves of `waves` waves each, every
/// octave twice the frequency and `gain` times the amplitude of the one before. Shared by the
/// detail noise here and the rough-wall relief (crate::detail::walls).
#[derive(Debug, Clone, Copy)]
pub struct Spectrum {
    pub octaves: usize,
    pub waves: usize,
    pub gain: f64,
}

impl Spectrum {
    /// `octaves × waves` waves of uniformly random direction on the sphere and phase.
    pub fn draw(self, random: &mut Random) -> Vec<Wave> {
        (0..self.octaves * self.waves)
            .map(|_| {
                let z = random.range(-1.0, 1.0);
                let a = random.range(0.0, std::f64::consts::TAU);
                let s = (1.0 - z * z).sqrt();
                let direction = [(s * a.cos()) as f32, (s * a.sin()) as f32, z as f32];
                Wave { direction, phase: random.range(0.0, std::f64::consts::TAU) as f32 }
            })
            .collect()
    }

    /// W = Σ_o g^o, which normalises the amplitudes so that values lie in [−1, 1].
    fn weight(self) -> f64 {
        (0..self.octaves).map(|o| self.gain.powi(o as i32)).sum()
    }

    /// The sum at `p` of `waves` whose longest wavelength is `wavelength` metres, in [−1, 1].
    pub fn value(self, waves: &[Wave], wavelength: f64, p: DVec3) -> f64 {
        let mut sum = 0.0;
        let mut frequency = std::f64::consts::TAU / wavelength;
        let mut amplitude = 1.0 / (self.weight() * self.waves as f64);
        for octave in waves.chunks(self.waves) {
            for w in octave {
                let d = DVec3::new(w.direction[0] as f64, w.direction[1] as f64, w.direction[2] as f64);
                sum += amplitude * sine(frequency * d.dot(p) + w.phase as f64);
            }
            frequency *= 2.0;
            amplitude *= self.gain;
        }
        sum
    }

    /// Upper bound of the sum's gradient norm at longest wavelength `wavelength` (direction
    /// norms are rounded to f32, hence the small margin).
    pub fn gradient_bound(self, wavelength: f64) -> f64 {
        let sum: f64 = (0..self.octaves).map(|o| (self.gain * 2.0).powi(o as i32)).sum();
        sum * (std::f64::consts::TAU / wavelength) / self.weight() * (1.0 + 1e-6)
    }

    /// The least upper bound of |Σ_j c_j·a_j·ω_j·d_j| over c ∈ [−1, 1]ⁿ for these `waves`
    /// (a_j, ω_j, d_j each wave's amplitude, angular frequency and direction), which bounds
    /// the sum's gradient Σ_j a_j·ω_j·cos(ω_j d_j·p + φ_j)·d_j wherever its cosines are. The
    /// norm is convex in c, so its largest value on the cube is at a corner: the largest
    /// |Σ_j ±a_j ω_j d_j| over the sign patterns (half of them: a pattern and its negation
    /// give the same norm), visited in Gray-code order, one wave flipped per step. Tighter
    /// than [`Spectrum::gradient_bound`], which adds the norms as if all directions were
    /// aligned: random directions rarely are.
    pub fn gradient_bound_of(self, waves: &[Wave], wavelength: f64) -> f64 {
        let mut terms = Vec::with_capacity(waves.len());
        let mut frequency = std::f64::consts::TAU / wavelength;
        let mut amplitude = 1.0 / (self.weight() * self.waves as f64);
        for octave in waves.chunks(self.waves) {
            for w in octave {
                let d = DVec3::new(w.direction[0] as f64, w.direction[1] as f64, w.direction[2] as f64);
                terms.push(d * (amplitude * frequency));
            }
            frequency *= 2.0;
            amplitude *= self.gain;
        }
        // The first wave keeps its sign; the others take both.
        let rest = terms.get(1..).unwrap_or_default();
        let mut sum: DVec3 = terms.iter().copied().sum();
        let mut signs = vec![1.0; rest.len()];
        let mut largest = sum.length_squared();
        for step in 1u64..1 << rest.len() {
            let flip = step.trailing_zeros() as usize;
            signs[flip] = -signs[flip];
            sum += rest[flip] * (2.0 * signs[flip]);
            largest = largest.max(sum.length_squared());
        }
        largest.sqrt() * (1.0 + 1e-6)
    }

    /// Checks decoded waves: the `octaves × waves` waves of unit direction the gradient bound
    /// assumes, with phases of sane size.
    pub fn validate(self, field: &str, waves: &[Wave]) -> Result<(), karst_artifact::Invalid> {
        use karst_artifact::check;
        check::count(|| format!("{field}.waves"), waves.len(), self.octaves * self.waves)?;
        for (i, w) in waves.iter().enumerate() {
            let norm = w.direction.iter().map(|c| (*c as f64).powi(2)).sum::<f64>().sqrt();
            check::within(|| format!("{field}.waves[{i}].direction"), norm, 1.0 - 1e-6, 1.0 + 1e-6)?;
            check::within(|| format!("{field}.waves[{i}].phase"), w.phase as f64, -1e3, 1e3)?;
        }
        Ok(())
    }
}

/// sin(x), accurate to about 2e-16 for |x| up to [`REDUCED`] (beyond, the standard library's).
///
/// The waves' arguments are world coordinates times up to tens of radians per metre: 10⁸ rad and
/// more on a projected terrain, where the C library's sine leaves its fast reduction (47 ns a
/// call against 10 ns below, measured here). Here x = k·π/2 + r with π/2 in three parts (24, 24
/// and 53 bits), so k·part is exact for |k| < 2²⁹ and r is found to the last bit of |r| ≤ π/4;
/// then the Taylor polynomials of sin r and cos r to degree 15 and 16 (remainders below 5e-17
/// there).
fn sine(x: f64) -> f64 {
    if x.is_nan() || x.abs() >= REDUCED {
        return x.sin();
    }
    // x·2/π rounded to the nearest integer by adding and removing 1.5·2⁵² (exact below 2⁵¹;
    // `f64::round` is a call into the C library).
    let k = (x * std::f64::consts::FRAC_2_PI + ROUNDING) - ROUNDING;
    let r = ((x - k * HALF_PI[0]) - k * HALF_PI[1]) - k * HALF_PI[2];
    let z = r * r;
    let sin = r + r * z * horner(z, &SIN);
    let cos = 1.0 - 0.5 * z + z * z * horner(z, &COS);
    // The quadrant k mod 4 picks ±sin r or ±cos r: both computed and selected without a branch
    // (the quadrants of successive waves are random, a branch on them mispredicts).
    let quadrant = k as i64 as u64;
    let value = if quadrant & 1 == 0 { sin } else { cos };
    f64::from_bits(value.to_bits() ^ ((quadrant & 2) << 62))
}

/// |x| below which [`sine`] reduces the argument itself: k = x·2/π stays below 2²⁹.
const REDUCED: f64 = 8.0e8;
const ROUNDING: f64 = 6_755_399_441_055_744.0;
/// π/2 = HALF_PI[0] + HALF_PI[1] + HALF_PI[2] to about 10⁻³¹, the first two of 24 bits.
const HALF_PI: [f64; 3] = [1.570_796_370_506_286_6, -4.371_138_828_673_793e-8, -1.715_124_499_442_883e-15];
/// sin r = r + r·z·(SIN[0] + z·SIN[1] + …), z = r²: −1/3!, 1/5!, … −1/15!.
const SIN: [f64; 7] = [
    -1.0 / 6.0,
    1.0 / 120.0,
    -1.0 / 5_040.0,
    1.0 / 362_880.0,
    -1.0 / 39_916_800.0,
    1.0 / 6_227_020_800.0,
    -1.0 / 1_307_674_368_000.0,
];
/// cos r = 1 − z/2 + z²·(COS[0] + z·COS[1] + …): 1/4!, −1/6!, … 1/16!.
const COS: [f64; 7] = [
    1.0 / 24.0,
    -1.0 / 720.0,
    1.0 / 40_320.0,
    -1.0 / 3_628_800.0,
    1.0 / 479_001_600.0,
    -1.0 / 87_178_291_200.0,
    1.0 / 20_922_789_888_000.0,
];

/// c[0] + z·c[1] + z²·c[2] + …
fn horner(z: f64, c: &[f64]) -> f64 {
    c.iter().rev().fold(0.0, |acc, &ci| acc * z + ci)
}

/// One plane wave of an octave: unit direction and phase.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Wave {
    pub direction: [f32; 3],
    pub phase: f32,
}

/// The noise: the waves of [`SPECTRUM`] at base wavelength `wavelength` metres.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct WaveNoise {
    pub wavelength: f64,
    pub waves: Vec<Wave>,
}

impl WaveNoise {
    /// A noise of base wavelength `wavelength` (metres) drawn from `random`.
    pub fn draw(random: &mut Random, wavelength: f64) -> Self {
        WaveNoise { wavelength, waves: SPECTRUM.draw(random) }
    }

    /// n(p) ∈ [−1, 1].
    pub fn value(&self, p: DVec3) -> f64 {
        SPECTRUM.value(&self.waves, self.wavelength, p)
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

    /// Checks a decoded noise: a finite base wavelength > 0 and the waves of unit direction
    /// its gradient bound (hence the field's 1-Lipschitz bound) assumes.
    pub fn validate(&self, field: &str) -> Result<(), karst_artifact::Invalid> {
        use karst_artifact::check::{self, MAX_COORDINATE};
        check::positive(|| format!("{field}.wavelength"), self.wavelength, MAX_COORDINATE)?;
        SPECTRUM.validate(field, &self.waves)
    }

    /// Upper bound of |∇n|.
    pub fn gradient_bound(&self) -> f64 {
        SPECTRUM.gradient_bound(self.wavelength)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::testing::Pairs;

    #[test]
    fn the_tight_bound_holds_the_gradient_and_is_below_the_sum_of_the_waves() {
        let spectrum = Spectrum { octaves: 5, waves: 3, gain: 0.6 };
        let waves = spectrum.draw(&mut Random::stream(8, "sdf", "test"));
        let (tight, loose) = (spectrum.gradient_bound_of(&waves, 4.0), spectrum.gradient_bound(4.0));
        assert!(tight < 0.9 * loose, "{tight} vs {loose}");
        // The gradient by central differences at many points stays below the tight bound.
        let mut steepest: f64 = 0.0;
        for (p, _) in Pairs::new(21, 40.0, 1.0).take(50_000) {
            let h = 1e-5;
            let d = |axis: DVec3| {
                (spectrum.value(&waves, 4.0, p + axis * h) - spectrum.value(&waves, 4.0, p - axis * h))
                    / (2.0 * h)
            };
            let gradient = DVec3::new(d(DVec3::X), d(DVec3::Y), d(DVec3::Z)).length();
            assert!(gradient <= tight * (1.0 + 1e-4), "{gradient} > {tight} at {p}");
            steepest = steepest.max(gradient);
        }
        assert!(steepest > 0.5 * tight, "{steepest} vs {tight}");
    }

    #[test]
    fn the_waves_sine_is_the_sine_to_the_last_bits_at_world_coordinates() {
        let mut random = Random::stream(5, "sdf", "test");
        let mut worst: f64 = 0.0;
        for scale in [1.0, 10.0, 1e3, 1e6, 1e8, 7.9e8, 2e9] {
            for _ in 0..20_000 {
                let x = random.range(-scale, scale);
                worst = worst.max((sine(x) - x.sin()).abs());
            }
        }
        assert!(worst < 1e-15, "{worst}");
        // Quadrant edges: k·π/2 on either side, where sine switches polynomials.
        for k in [1.0, 2.0, 3.0, 4.0, 1e6, 1e8 + 1.0, 5e8 + 3.0] {
            let edge = k * std::f64::consts::FRAC_PI_2;
            for x in [edge.next_down(), edge, edge.next_up()] {
                assert!((sine(x) - x.sin()).abs() < 1e-15, "{x}");
            }
        }
        assert!(sine(f64::NAN).is_nan() && sine(f64::INFINITY).is_nan());
    }

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
