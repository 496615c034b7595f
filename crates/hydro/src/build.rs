//! The hydro stage's algorithm entry: the sinks' recharge and the springs from the scene, then
//! the hydraulics of the network.

use karst_geology::params::Recharge;
use karst_geology::{KeyPointKind, Scene};
use karst_skeleton::Skeleton;

use crate::error::HydroError;
use crate::hydraulics::{Inputs, compute};
use crate::payload::Hydro;
use crate::recharge;

/// The water of `skeleton` under the scene's springs, recharge and `[hydro]` parameters.
pub fn build(scene: &Scene, skeleton: &Skeleton) -> Result<Hydro, HydroError> {
    if scene.hydro().recharge == Recharge::Catchment {
        recharge::check(scene)?;
    }
    let inputs = Inputs {
        spring_names: scene.keypoints_of(KeyPointKind::Spring).map(|(_, k)| k.name.clone()).collect(),
        recharge: match scene.hydro().recharge {
            Recharge::Weight => Vec::new(),
            Recharge::Catchment => recharge::catchments(scene)
                .into_iter()
                .zip(scene.keypoints_of(KeyPointKind::Sink))
                .map(|((name, area), (_, k))| (name, area * k.weight))
                .collect(),
        },
    };
    compute(skeleton, scene.hydro(), &inputs)
}
