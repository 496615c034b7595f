//! The terrain: the ground surface z = h(x, y) that bounds the bedrock from above.
//!
//! Three kinds: a (tilted) plane, a heightfield read from a 16-bit grayscale PNG or an OpenEXR
//! image with its georeferencing ([`crate::heightfield`]) or from a GeoTIFF ([`crate::grids`]),
//! and analytic value noise (rolling karst plateau).
//! The SDF stage needs h's Lipschitz bound λ (its steepest slope) to build the 1-Lipschitz
//! terrain distance (z − h)/√(1 + λ²) of Paris et al. 2021, appendix A.

use std::sync::Arc;

use serde::{Deserialize, Serialize};

use crate::heightfield::HeightGrid;

/// The ground surface (`[terrain]`).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(tag = "kind", rename_all = "snake_case", deny_unknown_fields)]
pub enum Terrain {
    /// A plane through `elevation` at `origin`, rising by `gradient` = [dz/dx, dz/dy]; the
    /// default gradient [0, 0] is a flat terrain.
    Plane {
        /// Elevation at `origin`, metres.
        elevation: f64,
        /// The point `[x, y]` where the elevation is given; default `[0, 0]`.
        #[serde(default)]
        origin: [f64; 2],
        /// Slope along x and y (dimensionless, 0.05 = 5 %); default flat.
        #[serde(default)]
        gradient: [f64; 2],
    },
    /// A heightfield image: elevation = offset + vertical_scale · pixel value.
    Heightfield {
        /// 16-bit (or 8-bit) grayscale PNG, OpenEXR (`.exr`) or GeoTIFF (`.tif`, `.tiff`),
        /// relative to the scene file's folder.
        file: String,
        /// `[x, y]` of the south-west pixel (bottom-left of the image); PNG and EXR only (a
        /// GeoTIFF carries its georeferencing).
        #[serde(default, skip_serializing_if = "Option::is_none")]
        origin: Option<[f64; 2]>,
        /// Ground distance between pixels, metres; PNG and EXR only.
        #[serde(default, skip_serializing_if = "Option::is_none")]
        cell_size: Option<f64>,
        /// Metres per pixel unit; default 1.
        #[serde(default = "one")]
        vertical_scale: f64,
        /// Elevation of pixel value 0; default 0.
        #[serde(default)]
        offset: f64,
        /// Pixel value meaning "no data"; default none (a GeoTIFF's GDAL_NODATA).
        #[serde(default, skip_serializing_if = "Option::is_none")]
        nodata: Option<f64>,
        /// BLAKE3 of the file's bytes, filled when the scene is loaded (so that editing the
        /// image reruns the stages).
        #[serde(default, skip_deserializing)]
        content: String,
        /// The elevations, filled when the scene is loaded.
        #[serde(skip)]
        grid: Arc<HeightGrid>,
    },
    /// Value noise: elevation + Σ_o amplitude·2^−o · n(2^o·(x, y)/wavelength), n a smooth
    /// (cubic Hermite) interpolation of pseudo-random lattice values in [−1, 1], x and y
    /// measured from the domain's south-west corner (so that a moved scene carries its terrain
    /// with it).
    Noise {
        /// Mean elevation, metres.
        elevation: f64,
        /// Amplitude of the first octave, metres.
        amplitude: f64,
        /// Wavelength of the first octave, metres.
        wavelength: f64,
        /// Number of octaves; default 3.
        #[serde(default = "three")]
        octaves: u32,
        /// Slope added to the noise, as for a plane; default flat.
        #[serde(default)]
        gradient: [f64; 2],
        /// Where x and y are measured from: the domain's `[min x, min y]`, set when the scene
        /// is loaded ([0, 0] once it is localized).
        #[serde(skip)]
        anchor: [f64; 2],
    },
}

/// Most octaves of a noise terrain: each halves the amplitude, so beyond a few dozen they add
/// nothing but evaluation time.
pub const MAX_OCTAVES: u32 = 24;

fn one() -> f64 {
    1.0
}

fn three() -> u32 {
    3
}

impl Terrain {
    /// Elevation of the ground at (x, y).
    #[inline]
    pub fn height(&self, x: f64, y: f64) -> f64 {
        match self {
            Terrain::Plane { elevation, origin, gradient } => {
                elevation + gradient[0] * (x - origin[0]) + gradient[1] * (y - origin[1])
            }
            Terrain::Heightfield { grid, .. } => grid.height(x, y),
            Terrain::Noise { elevation, amplitude, wavelength, octaves, gradient, anchor } => {
                let (x, y) = (x - anchor[0], y - anchor[1]);
                elevation
                    + gradient[0] * x
                    + gradient[1] * y
                    + noise_sum(x, y, *amplitude, *wavelength, *octaves)
            }
        }
    }

    /// Whether `p` is in the bedrock: inside `domain` and below the ground (no-karst volumes
    /// included).
    #[inline]
    pub fn in_bedrock(&self, domain: &crate::Domain, p: crate::Point) -> bool {
        domain.contains(p) && p.z < self.height(p.x, p.y)
    }

    /// Lipschitz bound λ of the height function: |h(a) − h(b)| ≤ λ |a − b|.
    pub fn lipschitz(&self) -> f64 {
        match self {
            Terrain::Plane { gradient, .. } => gradient[0].hypot(gradient[1]),
            Terrain::Heightfield { grid, .. } => grid.lipschitz,
            // Each octave's partial derivatives are at most 1.5 · 2 · amplitude_o / wavelength_o
            // (Hermite slope 1.5 times the largest lattice difference), and amplitude_o /
            // wavelength_o is the same for every octave.
            Terrain::Noise { amplitude, wavelength, octaves, gradient, .. } => {
                gradient[0].hypot(gradient[1])
                    + *octaves as f64 * 3.0 * std::f64::consts::SQRT_2 * amplitude.abs() / wavelength
            }
        }
    }
}

fn noise_sum(x: f64, y: f64, amplitude: f64, wavelength: f64, octaves: u32) -> f64 {
    (0..octaves)
        .map(|o| {
            let f = (1u64 << o) as f64 / wavelength;
            amplitude / (1u64 << o) as f64 * value_noise(x * f, y * f, o)
        })
        .sum()
}

/// Smoothly interpolated lattice noise in [−1, 1].
fn value_noise(x: f64, y: f64, octave: u32) -> f64 {
    let (i, j) = (x.floor(), y.floor());
    let (fx, fy) = (hermite(x - i), hermite(y - j));
    let v = |di: f64, dj: f64| lattice((i + di) as i64, (j + dj) as i64, octave);
    let south = v(0.0, 0.0) + (v(1.0, 0.0) - v(0.0, 0.0)) * fx;
    let north = v(0.0, 1.0) + (v(1.0, 1.0) - v(0.0, 1.0)) * fx;
    south + (north - south) * fy
}

fn hermite(t: f64) -> f64 {
    t * t * (3.0 - 2.0 * t)
}

/// A pseudo-random value in [−1, 1] per lattice node (integer hash, portable).
fn lattice(i: i64, j: i64, octave: u32) -> f64 {
    let mut h = (i as u64).wrapping_mul(0x9E37_79B9_7F4A_7C15)
        ^ (j as u64).wrapping_mul(0xC2B2_AE3D_27D4_EB4F)
        ^ (octave as u64).wrapping_mul(0x1656_67B1_9E37_79F9);
    h ^= h >> 29;
    h = h.wrapping_mul(0xBF58_476D_1CE4_E5B9);
    h ^= h >> 32;
    (h >> 11) as f64 / (1u64 << 52) as f64 - 1.0
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn tilted_plane() {
        let t = Terrain::Plane { elevation: 100.0, origin: [10.0, 0.0], gradient: [0.03, -0.04] };
        assert!((t.height(110.0, 100.0) - (100.0 + 3.0 - 4.0)).abs() < 1e-12);
        assert!((t.lipschitz() - 0.05).abs() < 1e-15);
    }

    #[test]
    fn noise_respects_its_lipschitz_bound() {
        let t = Terrain::Noise {
            elevation: 50.0,
            amplitude: 8.0,
            wavelength: 100.0,
            octaves: 3,
            gradient: [0.01, 0.0],
            anchor: [0.0; 2],
        };
        let lambda = t.lipschitz();
        let mut steepest = 0.0f64;
        for k in 0..2000 {
            let (x, y) = (k as f64 * 1.37, (k * 7 % 300) as f64 * 0.91);
            let d = 0.05;
            let slope = (t.height(x + d, y) - t.height(x, y)).abs() / d;
            steepest = steepest.max(slope);
            assert!((t.height(x, y) - 50.0 - 0.01 * x).abs() <= 8.0 * 1.75 + 1e-9);
        }
        assert!(steepest <= lambda && steepest > 0.02, "{steepest} vs {lambda}");
    }
}
