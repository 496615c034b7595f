//! The two falloff functions of the cost models: both 0 on the surface and 1 from the
//! distance of influence on.

/// Paris et al. 2021 §4.2: g(x) = 3x² − 2x³ on [0, 1], 0 below, 1 above (x = d / r).
pub fn smoothstep(x: f64) -> f64 {
    let x = x.clamp(0.0, 1.0);
    x * x * (3.0 - 2.0 * x)
}

/// KarstNSim eq. (2), after Wyvill's falloff: s(d) = 1 − (1 − d/d_max)³ for d < d_max, 1 beyond.
/// Steep near the surface, flat at d_max.
pub fn wyvill(d: f64, d_max: f64) -> f64 {
    let x = (d / d_max).clamp(0.0, 1.0);
    1.0 - (1.0 - x).powi(3)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn falloffs_go_from_zero_to_one() {
        assert_eq!(smoothstep(0.0), 0.0);
        assert_eq!(smoothstep(0.5), 0.5);
        assert_eq!(smoothstep(2.0), 1.0);
        assert_eq!(wyvill(0.0, 10.0), 0.0);
        assert_eq!(wyvill(5.0, 10.0), 0.875);
        assert_eq!(wyvill(12.0, 10.0), 1.0);
    }
}
