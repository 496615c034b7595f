//! Building the SDF model from the skeleton: one capsule per conduit segment.

use karst_artifact::StageError;
use karst_geology::Scene;
use karst_hydro::Hydro;
use karst_skeleton::Skeleton;

use crate::terrain::TerrainField;
use crate::{Capsule, SdfModel};

/// The model of `scene` carved by the conduits of `skeleton`. Each segment's capsule takes the
/// mean of its two node radii, times `sdf.radius_scale`.
pub fn build(scene: &Scene, skeleton: &Skeleton, hydro: &Hydro) -> Result<SdfModel, StageError> {
    if hydro.conduits.len() != skeleton.conduits.len() {
        return Err(StageError::input(format!(
            "hydro.json describes {} conduits, skeleton.json has {}: rerun `cargo xtask run --from hydro`",
            hydro.conduits.len(),
            skeleton.conduits.len()
        )));
    }
    let mut capsules = Vec::new();
    for (c, conduit) in skeleton.conduits.iter().enumerate() {
        if conduit.radius.len() != conduit.nodes.len() {
            return Err(StageError::input(format!(
                "skeleton.json: conduit {c} has {} nodes but {} radii",
                conduit.nodes.len(),
                conduit.radius.len()
            )));
        }
        for (i, w) in conduit.nodes.windows(2).enumerate() {
            let [a, b] = [w[0], w[1]].map(|n| skeleton.nodes.get(n as usize).map(|n| n.position));
            let (Some(a), Some(b)) = (a, b) else {
                return Err(StageError::input(format!(
                    "skeleton.json: conduit {c} names a node that does not exist"
                )));
            };
            let radius = 0.5 * (conduit.radius[i] + conduit.radius[i + 1]) * scene.sdf.radius_scale;
            if !(radius > 0.0 && radius.is_finite() && a.iter().chain(&b).all(|v| v.is_finite())) {
                return Err(StageError::input(format!(
                    "skeleton.json: conduit {c}, segment {i} has radius {radius} or a non-finite node; radii must be > 0"
                )));
            }
            capsules.push(Capsule { a, b, radius });
        }
    }
    Ok(SdfModel { domain: scene.domain, terrain: TerrainField::of(&scene.terrain), capsules })
}
