//! The hydro stage's algorithm entry: the sinks' recharge and the springs from the scene, then
//! the hydraulics of the network.

use karst_scene::params::Recharge;
use karst_scene::{KeyPointKind, keypoints_of};
use karst_skeleton::Skeleton;

use crate::error::HydroError;
use crate::hydraulics::{Inputs, compute};
use crate::payload::Hydro;
use crate::recharge;
use crate::view::HydroView;

/// The water of `skeleton` under the scene's springs, recharge and `[hydro]` parameters.
pub fn build(view: &HydroView, skeleton: &Skeleton) -> Result<Hydro, HydroError> {
    if view.hydro.recharge == Recharge::Catchment {
        recharge::check(view)?;
    }
    let inputs = Inputs {
        spring_names: keypoints_of(view.keypoints, KeyPointKind::Spring)
            .map(|(_, k)| k.name.clone())
            .collect(),
        recharge: match view.hydro.recharge {
            Recharge::Weight => Vec::new(),
            Recharge::Catchment => recharge::catchments(view)
                .into_iter()
                .zip(keypoints_of(view.keypoints, KeyPointKind::Sink))
                .map(|((name, area), (_, k))| (name, area * k.weight))
                .collect(),
        },
    };
    compute(skeleton, view.hydro, &inputs)
}
