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
        }
    }
}

impl HydroParams {
    pub(crate) fn check(&self, c: &mut Checks) {
        c.positive("hydro.catchment_cell", self.catchment_cell);
        c.positive("hydro.total_discharge", self.total_discharge);
        c.positive("hydro.speed_factor", self.speed_factor);
        c.positive("hydro.min_slope", self.min_slope);
        c.positive("hydro.radius_exponent", self.radius_exponent);
        if let Some([lo, hi]) = self.flow_radius {
            c.positive("hydro.flow_radius", lo);
            if lo.is_finite() && hi.is_finite() && hi < lo {
                c.report("hydro.flow_radius", format!("[{lo}, {hi}] is not a range (max < min)"));
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use std::path::Path;

    use crate::{Scene, SceneError};

    const SCENE: &str = "name = \"t\"\nseed = 1\n[domain]\nmin = [0, 0, 0]\nmax = [100, 100, 50]\n\
        [terrain]\nkind = \"plane\"\nelevation = 40\n[[geology.water_tables]]\nname = \"wt\"\nelevation = 10\n\
        [[keypoints]]\nname = \"a\"\nkind = \"sink\"\nposition = [10, 10, 40]\n\
        [[keypoints]]\nname = \"s\"\nkind = \"spring\"\nposition = [90, 90, 10]\nwater_table = \"wt\"\n";

    fn problems(hydro: &str) -> Vec<String> {
        match Scene::parse(&format!("{SCENE}[hydro]\n{hydro}\n"), Path::new("s.toml")) {
            Ok(_) => vec![],
            Err(SceneError::Invalid { problems, .. }) => problems.iter().map(|p| p.to_string()).collect(),
            Err(e) => vec![e.to_string()],
        }
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
}
