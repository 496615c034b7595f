//! Conduit radii (Paris et al. 2021 §5.3): epikarst segments get `skeleton.epikarst_radius`;
//! elsewhere the radius follows a 1D Gaussian process along the conduit's arc length, mapped to
//! `skeleton.radius` = [min, max].
//!
//! The process has the exponential covariance exp(−|Δs| / L), with L drawn per conduit in
//! `skeleton.radius_correlation`. For that covariance the values along a polyline are exactly
//! an order-1 autoregression: z₀ ~ N(0, 1), z_{i+1} = ρ z_i + √(1 − ρ²) ε, ρ = exp(−Δs / L), so
//! sampling costs O(n). The radius is min + (max − min) Φ(z) (Φ the standard normal CDF):
//! uniform marginals over the range, correlated along the conduit. A conduit that starts
//! where an earlier one already set the value starts from it, so radii are continuous at the
//! junctions the conduits are drawn from.

use glam::DVec3;
use karst_scene::params::SkeletonParams;
use karst_scene::rng::Random;

use crate::payload::{ConduitType, Node};

/// Radii of the conduits' nodes, drawn in conduit order.
pub struct ConduitRadii<'a> {
    params: &'a SkeletonParams,
    rng: Random,
    /// The process value already drawn at each node.
    value: Vec<Option<f64>>,
}

impl<'a> ConduitRadii<'a> {
    pub fn new(params: &'a SkeletonParams, seed: u64, node_count: usize) -> Self {
        ConduitRadii {
            params,
            rng: Random::stream(seed, "skeleton", "radius"),
            value: vec![None; node_count],
        }
    }

    /// The radius at each node of `chain`, whose segments have `types`.
    pub fn conduit(&mut self, nodes: &[Node], chain: &[u32], types: &[ConduitType]) -> Vec<f64> {
        let p = self.params;
        let [c0, c1] = p.radius_correlation;
        let range = self.rng.range(c0, c1);
        let mut z = match self.value[chain[0] as usize] {
            Some(z) => z,
            None => self.normal(),
        };
        let mut values = vec![z];
        for w in chain.windows(2) {
            let at = |i: u32| DVec3::from_array(nodes[i as usize].position);
            let rho = (-at(w[0]).distance(at(w[1])) / range).exp();
            z = rho * z + (1.0 - rho * rho).sqrt() * self.normal();
            values.push(z);
        }
        let [lo, hi] = p.radius;
        chain
            .iter()
            .zip(&values)
            .enumerate()
            .map(|(i, (&node, &z))| {
                self.value[node as usize].get_or_insert(z);
                let before = i.checked_sub(1).map(|j| types[j]);
                let after = types.get(i).copied();
                if [before, after].contains(&Some(ConduitType::Epikarst)) {
                    p.epikarst_radius
                } else {
                    lo + (hi - lo) * normal_cdf(z)
                }
            })
            .collect()
    }

    /// A standard normal draw (Box–Muller).
    fn normal(&mut self) -> f64 {
        let u = 1.0 - self.rng.uniform();
        let v = self.rng.uniform();
        (-2.0 * u.ln()).sqrt() * (std::f64::consts::TAU * v).cos()
    }
}

/// Φ(z), the standard normal CDF (Abramowitz & Stegun 7.1.26, error below 1.5e-7).
pub fn normal_cdf(z: f64) -> f64 {
    let x = z.abs() / std::f64::consts::SQRT_2;
    let t = 1.0 / (1.0 + 0.3275911 * x);
    let poly =
        t * (0.254829592 + t * (-0.284496736 + t * (1.421413741 + t * (-1.453152027 + t * 1.061405429))));
    let erf = 1.0 - poly * (-x * x).exp();
    if z >= 0.0 { 0.5 * (1.0 + erf) } else { 0.5 * (1.0 - erf) }
}

#[cfg(test)]
mod tests {
    use super::*;

    use crate::Zone;
    use karst_scene::Scene;
    use std::path::Path;

    fn scene() -> Scene {
        let text = r#"
name = "r"
[domain]
min = [0, 0, 0]
max = [3000, 10, 10]
[terrain]
kind = "plane"
elevation = 10
[[keypoints]]
name = "a"
kind = "sink"
position = [1, 1, 5]
[[keypoints]]
name = "s"
kind = "spring"
position = [2, 2, 5]
water_table = "w"
[[geology.water_tables]]
name = "w"
elevation = 1
[skeleton]
radius = [1.0, 3.0]
radius_correlation = [100.0, 100.0]
"#;
        Scene::parse(text, Path::new("r.toml")).unwrap()
    }

    fn straight_conduit(n: usize, step: f64) -> (Vec<Node>, Vec<u32>) {
        let nodes = (0..n)
            .map(|i| Node {
                position: [i as f64 * step, 5.0, 5.0],
                sample: 0,
                keypoint: None,
                zone: Zone::Vadose,
            })
            .collect();
        (nodes, (0..n as u32).collect())
    }

    #[test]
    fn radii_are_correlated_over_the_range_and_stay_in_bounds() {
        let scene = scene();
        let (nodes, chain) = straight_conduit(3000, 1.0);
        let types = vec![ConduitType::Canyon; chain.len() - 1];
        let r =
            ConduitRadii::new(scene.skeleton(), scene.seed(), nodes.len()).conduit(&nodes, &chain, &types);
        assert!(r.iter().all(|r| (1.0..=3.0).contains(r)));
        let mean = r.iter().sum::<f64>() / r.len() as f64;
        let correlation = |lag: usize| {
            let pairs = r.len() - lag;
            let c: f64 = (0..pairs).map(|i| (r[i] - mean) * (r[i + lag] - mean)).sum::<f64>() / pairs as f64;
            c / (r.iter().map(|x| (x - mean).powi(2)).sum::<f64>() / r.len() as f64)
        };
        assert!(correlation(5) > 0.9, "{}", correlation(5));
        assert!(correlation(400) < 0.5, "{}", correlation(400));
    }

    #[test]
    fn epikarst_segments_take_the_epikarst_radius() {
        let scene = scene();
        let (nodes, chain) = straight_conduit(4, 10.0);
        let types = [ConduitType::Epikarst, ConduitType::Tube, ConduitType::Tube];
        let r =
            ConduitRadii::new(scene.skeleton(), scene.seed(), nodes.len()).conduit(&nodes, &chain, &types);
        assert_eq!(&r[..2], &[0.5, 0.5]);
        assert!(r[2] >= 1.0 && r[3] >= 1.0);
    }

    #[test]
    fn normal_cdf_matches_known_values() {
        for (z, phi) in [(0.0, 0.5), (1.0, 0.841344746), (-1.96, 0.024997895), (3.0, 0.998650102)] {
            assert!((normal_cdf(z) - phi).abs() < 1e-6, "Φ({z})");
        }
    }
}
