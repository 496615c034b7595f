//! One section of parameters per stage, one file per section. Every field has a default, so a
//! scene only states what it changes; the hash of a section (defaults applied) is part of that
//! stage's artifact key. Each section checks its own values.

mod calibrate;
mod costgraph;
mod export;
mod hydro;
mod mesher;
mod sampling;
mod sdf;
mod skeleton;
mod streams;
#[cfg(test)]
mod test_scene;

pub use calibrate::{
    Aim, Bounds, CalibrateParams, DEFAULT_EVALUATIONS, MAX_SEEDS, PARAMETERS, Parameter, parameter,
};

pub use costgraph::{CostModelKind, CostgraphParams};
pub use export::{ExportFormat, ExportParams, MeshSurface};
pub use hydro::{HydroParams, PoolOutlet, PoolWeights, Recharge};
pub use mesher::MesherParams;
pub use sampling::{RadiusUnit, SamplingParams};
pub use sdf::{FULL_DETAIL_FIELDS, MAX_BREAKDOWN_BLOCKS, PassageDetail, SdfParams};
pub use skeleton::{Mode as SkeletonMode, SkeletonParams};
pub use streams::{Curve, CurveKind, StreamsParams};

/// Smallest conduit radius a scene may ask for, metres.
pub const MIN_RADIUS: f64 = 1e-3;
/// Largest conduit radius, metres.
pub const MAX_RADIUS: f64 = 1e3;
