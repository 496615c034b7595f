//! Why a construction tree cannot be built from a scene, its network and its water.

use karst_artifact::StageId;
use karst_stage::{Blame, Failure};

/// An sdf model that cannot be built.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum SdfError {
    #[error(transparent)]
    OverBudget(#[from] karst_scene::budget::OverBudget),
    #[error("describes {hydro} conduits, skeleton.json has {skeleton}")]
    ConduitCounts { hydro: usize, skeleton: usize },
    #[error("conduit {conduit} has fewer water segments than skeleton.json has segments")]
    WaterSegments { conduit: usize },
    #[error("terrain: no finite Lipschitz bound (λ = {lambda})")]
    TerrainNotLipschitz { lambda: f64 },
    #[error(
        "[sdf] ratio = {ratio} and asymmetry = {asymmetry} give conduits[{conduit}] node {node} \
         ({} / {}) a bad section: {problem}", types[0], types[1]
    )]
    BadSection {
        ratio: f64,
        asymmetry: f64,
        conduit: usize,
        node: usize,
        types: [&'static str; 2],
        problem: String,
    },
}

impl Failure for SdfError {
    fn blame(&self) -> Blame {
        match self {
            SdfError::ConduitCounts { .. } | SdfError::WaterSegments { .. } => {
                Blame::Artifact(StageId::Hydro)
            }
            SdfError::TerrainNotLipschitz { .. } | SdfError::BadSection { .. } | SdfError::OverBudget(_) => {
                Blame::Scene
            }
        }
    }
}
