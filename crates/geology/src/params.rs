//! One section of parameters per stage. Every field has a default, so a scene only states what
//! it changes; the hash of a section (defaults applied) is part of that stage's artifact key.

use serde::{Deserialize, Serialize};

/// `[sampling]`: Poisson-disk sampling of the bedrock.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct SamplingParams {
    /// Minimum distance between two samples, metres.
    pub radius: f64,
    /// Candidates tried around each active sample before it retires (Bridson's k).
    pub attempts: u32,
}

impl Default for SamplingParams {
    fn default() -> Self {
        SamplingParams { radius: 20.0, attempts: 30 }
    }
}

/// `[costgraph]`: the k-nearest-neighbour graph and its edge costs.
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

/// `[skeleton]`: the conduit network.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct SkeletonParams {
    /// Range `[min, max]` of conduit radii, metres; each conduit draws its radius uniformly.
    pub radius: [f64; 2],
}

impl Default for SkeletonParams {
    fn default() -> Self {
        SkeletonParams { radius: [0.5, 4.0] }
    }
}

/// `[hydro]`: flow through the network. No parameters yet: flows come from the sinks' weights.
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct HydroParams {}

/// `[sdf]`: the signed-distance model.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct SdfParams {
    /// Factor applied to every conduit radius.
    pub radius_scale: f64,
}

impl Default for SdfParams {
    fn default() -> Self {
        SdfParams { radius_scale: 1.0 }
    }
}

/// `[mesher]`: polygonization.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct MesherParams {
    /// Edge of the finest cell, metres.
    pub cell_size: f64,
}

impl Default for MesherParams {
    fn default() -> Self {
        MesherParams { cell_size: 2.0 }
    }
}

/// `[metrics]`: network statistics. No parameters yet.
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct MetricsParams {}
