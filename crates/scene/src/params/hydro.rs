//! `[hydro]`: flow through the network, water types and water geometry (docs/hydro.md).

use serde::{Deserialize, Serialize};

use crate::validate::Checks;

/// Where the sinks' recharge comes from.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Recharge {
    /// Each sink feeds its key point weight (default 1).
    Weight,
    /// Each sink feeds the area of terrain draining to it (D8 flow accumulation, m²) times
    /// its key point weight.
    Catchment,
}

#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct HydroParams {
    /// Source of the sinks' recharge.
    pub recharge: Recharge,
    /// Cell edge of the D8 grid on the terrain, metres (`recharge = "catchment"`).
    pub catchment_cell: f64,
    /// Discharge of the whole network at its springs, m³/s: the scale of the water geometry.
    pub total_discharge: f64,
    /// Speed of running water per radian of slope, m/s (Emilien et al. 2015 §5.2.2, k = 10).
    pub speed_factor: f64,
    /// Smallest slope used for the speed of running water, radians (flat conduits still flow).
    pub min_slope: f64,
    /// `[min, max]` radius of conduits sized from their flow, metres; absent: the skeleton's
    /// random radii are kept.
    pub flow_radius: Option<[f64; 2]>,
    /// Exponent a of the flow sizing: radius ∝ flow^a.
    pub radius_exponent: f64,
    /// User weights of the outgoing conduits of pools (`[[hydro.pools]]`); elsewhere pools
    /// split their water equally.
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub pools: Vec<PoolWeights>,
}

/// `[[hydro.pools]]`: how one pool shares its water among its outgoing conduits.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct PoolWeights {
    /// A point at the pool: the pool node of the network nearest to it, within `radius`.
    pub at: [f64; 3],
    /// How far from `at` the pool node may be, metres.
    #[serde(default = "default_pool_radius")]
    pub radius: f64,
    /// Each outgoing conduit takes the weight of the outlet whose direction from the pool is
    /// closest to its own (first listed on a tie).
    pub outlets: Vec<PoolOutlet>,
}

/// One outlet of a pool: a point the outgoing conduit heads towards, and its weight.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct PoolOutlet {
    pub towards: [f64; 3],
    pub weight: f64,
}

fn default_pool_radius() -> f64 {
    10.0
}

impl Default for HydroParams {
    fn default() -> Self {
        HydroParams {
            recharge: Recharge::Weight,
            catchment_cell: 10.0,
            total_discharge: 1.0,
            speed_factor: 10.0,
            min_slope: 0.01,
            flow_radius: None,
            radius_exponent: 0.5,
            pools: Vec::new(),
        }
    }
}

impl HydroParams {
    pub(crate) fn check(&self, c: &mut Checks) {
        c.positive("hydro.catchment_cell", self.catchment_cell);
        c.positive("hydro.total_discharge", self.total_discharge);
        c.positive("hydro.speed_factor", self.speed_factor);
        if c.within("hydro.min_slope", self.min_slope, 0.0, std::f64::consts::FRAC_PI_2)
            && self.min_slope == 0.0
        {
            c.report("hydro.min_slope", "must be > 0, got 0".into());
        }
        if c.within("hydro.radius_exponent", self.radius_exponent, 0.0, 10.0) && self.radius_exponent == 0.0 {
            c.report("hydro.radius_exponent", "must be > 0, got 0".into());
        }
        if let Some(range) = self.flow_radius {
            c.range("hydro.flow_radius", range, super::MIN_RADIUS, super::MAX_RADIUS);
        }
        for (i, pool) in self.pools.iter().enumerate() {
            let field = format!("hydro.pools[{i}]");
            c.coordinates(&format!("{field}.at"), &pool.at);
            c.positive(&format!("{field}.radius"), pool.radius);
            if pool.outlets.is_empty() {
                c.report(&format!("{field}.outlets"), "is empty: give at least one outlet".into());
            }
            for (j, outlet) in pool.outlets.iter().enumerate() {
                let field = format!("{field}.outlets[{j}]");
                if c.coordinates(&format!("{field}.towards"), &outlet.towards) && outlet.towards == pool.at {
                    c.report(&format!("{field}.towards"), "is the pool's own point: no direction".into());
                }
                c.non_negative(&format!("{field}.weight"), outlet.weight);
            }
            if !pool.outlets.is_empty() && pool.outlets.iter().all(|o| o.weight == 0.0) {
                c.report(
                    &format!("{field}.outlets"),
                    "every weight is 0: water could not leave the pool".into(),
                );
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use crate::params::test_scene;

    fn problems(hydro: &str) -> Vec<String> {
        test_scene::problems(&format!("[hydro]\n{hydro}"))
    }

    #[test]
    fn hydro_fields_are_checked() {
        assert!(problems("recharge = \"catchment\"\nflow_radius = [0.5, 3]").is_empty());
        let p = problems("catchment_cell = 0\nmin_slope = -1\nflow_radius = [2, 1]");
        assert_eq!(p.len(), 3, "{p:?}");
        assert!(p[0].contains("hydro.catchment_cell: must be > 0, got 0"), "{p:?}");
        assert!(p[2].contains("hydro.flow_radius: [2, 1] is not a range"), "{p:?}");
        assert!(problems("recharge = \"rain\"")[0].contains("unknown variant `rain`"));
    }

    #[test]
    fn pool_weights_are_checked() {
        let good = "[[hydro.pools]]\nat = [50, 50, 20]\noutlets = [{ towards = [90, 90, 10], weight = 3 }, { towards = [0, 50, 10], weight = 0 }]";
        assert!(problems(good).is_empty(), "{:?}", problems(good));
        let bad = "[[hydro.pools]]\nat = [50, 50, nan]\nradius = 0\noutlets = [{ towards = [1, 2, 3], weight = -1 }, { towards = [1, 2, 3], weight = nan }]";
        let p = problems(bad);
        assert!(p.iter().any(|m| m.contains("hydro.pools[0].at")), "{p:?}");
        assert!(p.iter().any(|m| m.contains("hydro.pools[0].radius: must be > 0, got 0")), "{p:?}");
        assert!(
            p.iter().any(|m| m.contains("hydro.pools[0].outlets[0].weight") && m.contains("-1")),
            "{p:?}"
        );
        assert!(
            p.iter().any(|m| m.contains("hydro.pools[0].outlets[1].weight") && m.contains("NaN")),
            "{p:?}"
        );
        let zero = "[[hydro.pools]]\nat = [50, 50, 20]\noutlets = [{ towards = [1, 2, 3], weight = 0 }]";
        assert!(problems(zero).iter().any(|m| m.contains("hydro.pools[0].outlets: every weight is 0")));
        let empty = "[[hydro.pools]]\nat = [50, 50, 20]\noutlets = []";
        assert!(problems(empty).iter().any(|m| m.contains("hydro.pools[0].outlets: is empty")));
        assert!(
            problems("[[hydro.pools]]\nat = [1, 2, 3]\noutlets = [{ toward = [1, 2, 4], weight = 1 }]")
                .iter()
                .any(|m| m.contains("unknown field `toward`"))
        );
    }
}
