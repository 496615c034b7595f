//! The cost of an edge: its length times the mean cost per metre of the rock it crosses.
//!
//! Cost per metre (Paris et al. 2021 §4.2, with the phreatic term of KarstNSim §1.3):
//! c(p) = 1 + w_L·g(d_L(p)/r_L) + w_P·g(depth(p)/r_P), where g(x) = 3x² − 2x³ on [0, 1]
//! (clamped), d_L the distance to the nearest inception horizon (conduits are drawn to
//! horizons: the term vanishes on them) and depth the depth below the highest water table
//! (deep phreatic conduits are discouraged). Without horizons that term is 0. The mean over
//! the edge is Simpson's rule on both ends and the middle, so a conduit cannot cut across a
//! costly layer by jumping over it between two cheap samples.

use glam::DVec3;

use karst_geology::{Scene, Surface};

/// Everything the cost of an edge depends on.
#[derive(Debug, Clone)]
pub struct CostModel {
    horizons: Vec<Surface>,
    water_tables: Vec<Surface>,
    horizon_weight: f64,
    horizon_distance: f64,
    phreatic_weight: f64,
    phreatic_distance: f64,
}

impl CostModel {
    pub fn from_scene(scene: &Scene) -> Self {
        let p = &scene.costgraph;
        CostModel {
            horizons: scene.geology.horizons.clone(),
            water_tables: scene.geology.water_tables.clone(),
            horizon_weight: p.horizon_weight,
            horizon_distance: p.horizon_distance,
            phreatic_weight: p.phreatic_weight,
            phreatic_distance: p.phreatic_distance,
        }
    }

    /// Cost per metre at `p`; always ≥ 1.
    pub fn per_metre(&self, p: DVec3) -> f64 {
        let horizon = match self.horizons.iter().map(|h| h.distance(p)).reduce(f64::min) {
            Some(d) => self.horizon_weight * smoothstep(d / self.horizon_distance),
            None => 0.0,
        };
        let depth =
            self.water_tables.iter().map(|w| -w.height_above(p)).reduce(f64::max).unwrap_or(0.0).max(0.0);
        1.0 + horizon + self.phreatic_weight * smoothstep(depth / self.phreatic_distance)
    }

    /// Cost of the edge a → b: length × mean cost per metre (Simpson's rule).
    pub fn edge_cost(&self, a: DVec3, b: DVec3) -> f64 {
        let mean = (self.per_metre(a) + 4.0 * self.per_metre((a + b) * 0.5) + self.per_metre(b)) / 6.0;
        a.distance(b) * mean
    }
}

/// g(x) = 3x² − 2x³ on [0, 1], 0 below, 1 above.
pub fn smoothstep(x: f64) -> f64 {
    let x = x.clamp(0.0, 1.0);
    x * x * (3.0 - 2.0 * x)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn model() -> CostModel {
        let plane = |name: &str, z: f64| Surface::plane(name, z, [0.0; 2], 0.0, 0.0);
        CostModel {
            horizons: vec![plane("h", 50.0)],
            water_tables: vec![plane("w", 20.0)],
            horizon_weight: 2.0,
            horizon_distance: 10.0,
            phreatic_weight: 1.0,
            phreatic_distance: 20.0,
        }
    }

    #[test]
    fn horizons_attract_and_depth_repels() {
        let m = model();
        assert_eq!(m.per_metre(DVec3::new(0.0, 0.0, 50.0)), 1.0);
        assert_eq!(m.per_metre(DVec3::new(0.0, 0.0, 30.0)), 3.0);
        assert_eq!(m.per_metre(DVec3::new(0.0, 0.0, 0.0)), 4.0);
        assert!((m.per_metre(DVec3::new(0.0, 0.0, 55.0)) - 2.0).abs() < 1e-12);
    }

    #[test]
    fn cost_is_integrated_along_the_edge() {
        let m = model();
        // Both ends 10 m from the horizon, the middle on it: the middle counts.
        let a = DVec3::new(0.0, 0.0, 40.0);
        let b = DVec3::new(0.0, 0.0, 60.0);
        let ends_only = a.distance(b) * m.per_metre(a);
        assert!(m.edge_cost(a, b) < ends_only);
        assert!(m.edge_cost(a, b) >= a.distance(b));
    }
}
