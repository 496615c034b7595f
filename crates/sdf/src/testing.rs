//! Random point pairs for the Lipschitz property tests.

use glam::DVec3;

/// Pairs (p, q): p uniform in a cube of half-side `extent` around `centre`, q within `reach`.
pub struct Pairs {
    state: u64,
    centre: DVec3,
    extent: f64,
    reach: f64,
}

impl Pairs {
    pub fn new(seed: u64, extent: f64, reach: f64) -> Self {
        Pairs { state: seed.wrapping_mul(0x9E37_79B9_7F4A_7C15) | 1, centre: DVec3::ZERO, extent, reach }
    }

    pub fn around(mut self, centre: DVec3) -> Self {
        self.centre = centre;
        self
    }

    fn next(&mut self) -> f64 {
        self.state = self.state.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
        (self.state >> 11) as f64 / (1u64 << 53) as f64 * 2.0 - 1.0
    }

    fn vector(&mut self) -> DVec3 {
        DVec3::new(self.next(), self.next(), self.next())
    }
}

impl Iterator for Pairs {
    type Item = (DVec3, DVec3);

    fn next(&mut self) -> Option<(DVec3, DVec3)> {
        let p = self.centre + self.vector() * self.extent;
        let q = p + self.vector() * self.reach;
        Some((p, q))
    }
}

/// Asserts |f(p) − f(q)| ≤ |p − q|·(1 + 1e-5) on `n` pairs.
pub fn assert_lipschitz(f: impl Fn(DVec3) -> f64, pairs: Pairs, n: usize) {
    for (p, q) in pairs.take(n) {
        let (fp, fq) = (f(p), f(q));
        assert!(
            (fp - fq).abs() <= p.distance(q) * (1.0 + 1e-5) + 1e-12,
            "f({p}) = {fp}, f({q}) = {fq}, |p − q| = {}",
            p.distance(q)
        );
    }
}
