//! `[costgraph]`: the k-nearest-neighbour graph and its edge costs.

use serde::{Deserialize, Serialize};

use crate::validate::Checks;

#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct CostgraphParams {
    /// Neighbours per sample.
    pub k: usize,
    /// Longest edge kept, metres; no limit when absent.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub max_edge_length: Option<f64>,
    /// Weight of the inception-horizon term (edges far from every horizon cost more).
    pub horizon_weight: f64,
    /// Distance beyond which a horizon no longer attracts conduits, metres.
    pub horizon_distance: f64,
    /// Weight of the depth-below-the-water-table term (deep phreatic edges cost more).
    pub phreatic_weight: f64,
    /// Depth below the water table at which that term saturates, metres.
    pub phreatic_distance: f64,
}

impl Default for CostgraphParams {
    fn default() -> Self {
        CostgraphParams {
            k: 20,
            max_edge_length: None,
            horizon_weight: 1.0,
            horizon_distance: 10.0,
            phreatic_weight: 1.0,
            phreatic_distance: 20.0,
        }
    }
}

impl CostgraphParams {
    pub(crate) fn check(&self, c: &mut Checks) {
        if self.k == 0 {
            c.report("costgraph.k", "must be ≥ 1".into());
        }
        if let Some(l) = self.max_edge_length {
            c.positive("costgraph.max_edge_length", l);
        }
        c.non_negative("costgraph.horizon_weight", self.horizon_weight);
        c.positive("costgraph.horizon_distance", self.horizon_distance);
        c.non_negative("costgraph.phreatic_weight", self.phreatic_weight);
        c.positive("costgraph.phreatic_distance", self.phreatic_distance);
    }
}
