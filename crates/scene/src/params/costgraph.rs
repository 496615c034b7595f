//! `[costgraph]`: the k-nearest-neighbour graph and its edge costs (docs/costgraph.md).

use serde::{Deserialize, Serialize};

use crate::validate::Checks;

/// Which cost function the edges carry.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum CostModelKind {
    /// Paris et al. 2021 §4.2: distance, horizon, fracture and permeability terms; one cost set.
    Paris2021,
    /// KarstNSim (Gouy et al. 2024 §1.3): weighted normalized terms; one cost set per water table
    /// named by a spring.
    Karstnsim2024,
}

#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct CostgraphParams {
    /// Neighbours per sample, 1 to 200.
    pub k: usize,
    /// Longest edge kept, metres; no limit when absent.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub max_edge_length: Option<f64>,
    /// Add the reverse of every edge that is missing, so that the graph is symmetric.
    pub symmetrise: bool,
    /// The cost function.
    pub model: CostModelKind,
    /// ε, cost per metre added to every edge so that no edge is free.
    pub cost_floor: f64,
    /// karstnsim2024: α_I, weight of the inception-surface term.
    pub alpha_inception: f64,
    /// karstnsim2024: α_F, weight of the fracture term.
    pub alpha_fracture: f64,
    /// When `[geology]` has no fracture family, assume two vertical joint sets 90° apart
    /// oriented along the terrain's lineaments (docs/costgraph.md, "Assumed joints").
    pub assumed_joints: bool,
    /// karstnsim2024: α_WT, weight of the water-table term.
    pub alpha_water_table: f64,
    /// karstnsim2024: α_P, weight of the karstification-potential term.
    pub alpha_potential: f64,
    /// karstnsim2024: d_max of the inception surfaces, metres.
    pub inception_distance: f64,
    /// karstnsim2024: d_max of the water table in the phreatic zone, metres.
    pub water_table_distance: f64,
    /// paris2021: w_dist, weight of the length itself.
    pub w_distance: f64,
    /// paris2021: w_L, weight of the horizon term.
    pub w_horizon: f64,
    /// paris2021: r, distance beyond which a horizon no longer attracts, metres.
    pub horizon_distance: f64,
    /// paris2021: w_F, weight of the fracture term.
    pub w_fracture: f64,
    /// paris2021: w_π, weight of the permeability (resistance 1 − P) term.
    pub w_permeability: f64,
    /// paris2021: cost per metre of the edges along a user-prescribed path
    /// (`skeleton.forced_links`), instead of the model's when that is higher.
    pub forced_link_cost: f64,
    /// paris2021: radius of the straight corridor of a forced link, metres: an edge whose two
    /// ends lie within it is along the link.
    pub forced_link_radius: f64,
}

impl Default for CostgraphParams {
    fn default() -> Self {
        CostgraphParams {
            k: 40,
            max_edge_length: None,
            symmetrise: false,
            model: CostModelKind::Karstnsim2024,
            cost_floor: 0.01,
            alpha_inception: 1.0,
            alpha_fracture: 1.0,
            assumed_joints: true,
            alpha_water_table: 1.0,
            alpha_potential: 1.0,
            inception_distance: 10.0,
            water_table_distance: 20.0,
            w_distance: 1.0,
            w_horizon: 1.0,
            horizon_distance: 10.0,
            w_fracture: 1.0,
            w_permeability: 1.0,
            forced_link_cost: 0.1,
            forced_link_radius: 15.0,
        }
    }
}

/// The largest `k` accepted.
pub const MAX_K: usize = 200;
/// Largest cost per metre and term weight: with edges of at most 1e6 m, no cost reaches the
/// 3.4e38 an f32 holds.
pub const MAX_COST_WEIGHT: f64 = 1e6;

impl CostgraphParams {
    pub(crate) fn check(&self, c: &mut Checks) {
        if self.k == 0 || self.k > MAX_K {
            c.report("costgraph.k", format!("must be in [1, {MAX_K}], got {}", self.k));
        }
        if let Some(l) = self.max_edge_length {
            c.positive("costgraph.max_edge_length", l);
        }
        // Bounded so that no edge cost overflows the artifact's f32 costs (docs/limits.md).
        c.within("costgraph.cost_floor", self.cost_floor, 1e-6, MAX_COST_WEIGHT);
        for (field, value) in [
            ("alpha_inception", self.alpha_inception),
            ("alpha_fracture", self.alpha_fracture),
            ("alpha_water_table", self.alpha_water_table),
            ("alpha_potential", self.alpha_potential),
            ("w_distance", self.w_distance),
            ("w_horizon", self.w_horizon),
            ("w_fracture", self.w_fracture),
            ("w_permeability", self.w_permeability),
        ] {
            c.within(&format!("costgraph.{field}"), value, 0.0, MAX_COST_WEIGHT);
        }
        for (field, value) in [
            ("inception_distance", self.inception_distance),
            ("water_table_distance", self.water_table_distance),
            ("horizon_distance", self.horizon_distance),
            ("forced_link_radius", self.forced_link_radius),
        ] {
            c.positive(&format!("costgraph.{field}"), value);
        }
        c.within("costgraph.forced_link_cost", self.forced_link_cost, 1e-6, MAX_COST_WEIGHT);
    }
}
