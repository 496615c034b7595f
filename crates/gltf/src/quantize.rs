//! KHR_mesh_quantization: positions as 16-bit integers on a grid, unit normals as signed
//! normalized bytes.
//!
//! Every piece of one surface shares one [`Quantization`], a grid of step `step` from the
//! surface's lowest corner, so that a vertex on the seam of two pieces gets the same integer
//! position in both and the pieces meet exactly. A piece stores its integers relative to its own
//! lowest grid point; its node's scale (the step) and translation (that point) turn them back
//! into metres.

/// Largest quantized coordinate.
const Q_MAX: f64 = 65535.0;

/// The integer grid positions of one surface are quantized on.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Quantization {
    pub origin: [f64; 3],
    /// Grid step, metres.
    pub step: f64,
}

impl Quantization {
    /// The grid over the box `min`..`max` with 2¹⁶ steps along its longest side.
    pub fn over(min: [f32; 3], max: [f32; 3]) -> Quantization {
        let extent = (0..3).map(|a| f64::from(max[a]) - f64::from(min[a])).fold(0.0, f64::max);
        let step = if extent > 0.0 { extent / Q_MAX } else { 1.0 };
        Quantization { origin: min.map(f64::from), step }
    }

    /// The grid coordinates of `p`.
    pub fn grid(&self, p: [f32; 3]) -> [u32; 3] {
        [0, 1, 2].map(|a| ((f64::from(p[a]) - self.origin[a]) / self.step).round().clamp(0.0, Q_MAX) as u32)
    }

    /// The position of grid point `g`, metres.
    pub fn point(&self, g: [u32; 3]) -> [f64; 3] {
        [0, 1, 2].map(|a| self.origin[a] + f64::from(g[a]) * self.step)
    }
}

/// A unit vector as three signed normalized bytes and a padding byte (glTF aligns vertex
/// attributes to 4 bytes).
pub fn snorm(v: [f32; 3]) -> [i8; 4] {
    let c = |x: f32| (x.clamp(-1.0, 1.0) * 127.0).round() as i8;
    [c(v[0]), c(v[1]), c(v[2]), 0]
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn grid_points_come_back_within_half_a_step() {
        let q = Quantization::over([-5.0, 0.0, 2.0], [95.0, 40.0, 12.0]);
        for p in [[-5.0, 0.0, 2.0], [95.0, 40.0, 12.0], [12.345, 6.789, 3.21]] {
            let back = q.point(q.grid(p));
            for a in 0..3 {
                assert!((back[a] - f64::from(p[a])).abs() <= 0.5 * q.step + 1e-9, "{p:?} -> {back:?}");
            }
        }
        assert_eq!(snorm([0.0, 0.6, 0.8]), [0, 76, 102, 0]);
    }
}
