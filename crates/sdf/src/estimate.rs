//! The sdf stage's work estimate, made before any leaf is built: with passage profiles every
//! segment is a sweep per profile piece and two run-ons; without, a straight conduit costs a
//! sweep and a joint sphere per segment, and a tortuous one (`sdf.tortuosity`) is cut into
//! cross-sections every `sdf.sphere_spacing` radii, each offering a lattice of candidate
//! spheres of that spacing over the section: the candidates grow as 1 / (spacing × radius)
//! along the conduit, which a tiny `sdf.radius_scale` makes unbounded.

use glam::DVec3;

use karst_scene::budget::{Cheaper, Estimate, OverBudget};
use karst_scene::params::SdfParams;
use karst_skeleton::{ConduitType, Skeleton};

use crate::tree::sweep::tortuosity;
use crate::view::SdfView;

/// Bytes per candidate sphere (centre, radius, station) while a segment is pruned, and per
/// leaf kept (with its share of the evaluable tree, BENCHMARKS.md: 39 B per primitive).
const BYTES_PER_PRIMITIVE: f64 = 64.0;
/// The section's extent over its half-width, at most (the tallest shapes, before `ratio`).
const EXTENT: f64 = 2.0;

/// Leaves and sphere candidates of `skeleton`'s conduits at radius scale `scale`.
fn primitives(p: &SdfParams, skeleton: &Skeleton, scale: f64) -> f64 {
    let mut total = 0.0;
    for conduit in &skeleton.conduits {
        if p.passage_detail.varies() {
            total += 3.0 * conduit.types.len() as f64 + conduit.profile.len() as f64;
            continue;
        }
        let points: Vec<DVec3> =
            conduit.nodes.iter().map(|&n| DVec3::from_array(skeleton.nodes[n as usize].position)).collect();
        let tortuous = tortuosity(&points) > p.tortuosity && points.len() > 2;
        for (i, w) in points.windows(2).enumerate() {
            if !tortuous || conduit.types[i] == ConduitType::Chamber {
                total += 2.0;
                continue;
            }
            let step = p.sphere_spacing * conduit.radius[i].min(conduit.radius[i + 1]) * scale;
            let stations = (w[0].distance(w[1]) / step).ceil().max(1.0) + 1.0;
            let cells = (EXTENT * p.ratio.max(1.0) / p.sphere_spacing).ceil();
            total += stations * (2.0 * cells + 1.0).powi(2);
        }
    }
    total
}

/// Refuses a model whose leaves would not fit in the memory budget.
pub fn check(view: &SdfView, skeleton: &Skeleton) -> Result<(), OverBudget> {
    let scale = view.sdf.radius_scale;
    let count = primitives(view.sdf, skeleton, scale);
    let estimate = Estimate {
        what: format!("{count:.2e} leaves and sphere candidates"),
        bytes: count * BYTES_PER_PRIMITIVE,
        field: "sdf.radius_scale".into(),
        value: scale,
    };
    view.budget
        .check(estimate, Cheaper::Larger, false, |s| primitives(view.sdf, skeleton, s) * BYTES_PER_PRIMITIVE)
}
