//! Sediment floors: low-gradient passages fill their lower part with clastic sediment (sand,
//! silt, clay) that slow water drops, leaving a flat floor (Ford & Williams 2007 §7.11; White
//! 1988 ch. 11: fills are thickest where the gradient is low and the flow sluggish).
//!
//! **The rule.** A segment of the skeleton whose gradient is below [`MAX_GRADIENT`], at least
//! [`MIN_LENGTH`] long, gets a flat fill whose top lies [`FILL`] of the passage height above the
//! floor, the lowest such level over stations every 2 m (floor and roof found by sphere
//! tracing), so that the fill never closes a pinch. The fill is a rounded box
//! along the segment, as wide as the passage at that height (traced sideways) plus a margin in
//! the walls, shortened by a radius at each end so that it stays out of the junctions; its
//! top face is the new floor. None where the middle of the fill would be under water.

use glam::{DQuat, DVec3};
use karst_scene::params::SdfParams;
use karst_skeleton::Skeleton;

use super::rock::{Piece, PieceKind, Shape};
use super::speleothems::trace;
use crate::field::carved::CarvedTerrain;

/// Steepest segment (rise over run) that holds a fill.
pub const MAX_GRADIENT: f64 = 0.03;
/// Shortest segment that holds a fill, metres.
pub const MIN_LENGTH: f64 = 4.0;
/// Fraction of the passage height the fill takes.
pub const FILL: f64 = 0.2;
/// Thickness of the fill below the floor and into the walls, metres.
const MARGIN: f64 = 0.5;
/// Spacing of the stations that bound the fill's top, metres.
const STEP: f64 = 2.0;

/// The fills of the network's low-gradient segments.
pub fn fills(field: &CarvedTerrain, skeleton: &Skeleton, p: &SdfParams) -> Vec<Piece> {
    let mut out = Vec::new();
    for conduit in &skeleton.conduits {
        for (i, w) in conduit.nodes.windows(2).enumerate() {
            let [a, b] = [w[0], w[1]].map(|n| DVec3::from_array(skeleton.nodes[n as usize].position));
            let radius = conduit.radius[i].min(conduit.radius[i + 1]) * p.radius_scale;
            let run = (b - a).truncate().length();
            let length = run - 2.0 * radius;
            if (b.z - a.z).abs() > MAX_GRADIENT * run || length < MIN_LENGTH {
                continue;
            }
            out.extend(fill(field, a, b, length));
        }
    }
    out
}

fn fill(field: &CarvedTerrain, a: DVec3, b: DVec3, length: f64) -> Option<Piece> {
    let along = (b - a).truncate().normalize().extend(0.0);
    let mid = (a + b) * 0.5;
    // The fill's top: the lowest of FILL of the height above the floor at stations every
    // STEP metres, so that it never closes the passage where it pinches.
    let count = (length / STEP).ceil() as usize;
    let mut top = f64::INFINITY;
    let mut floor_mid = f64::NAN;
    for k in 0..=count {
        let at = mid + along * (k as f64 / count as f64 - 0.5) * length;
        if field.cave(at) > -0.1 || field.water(at) < 0.0 {
            return None;
        }
        let roof = at.z + trace(field, at, DVec3::Z, 30.0)?;
        let floor = at.z - trace(field, at, -DVec3::Z, 30.0)?;
        top = top.min(floor + FILL * (roof - floor));
        if 2 * k == count || (floor_mid.is_nan() && 2 * k > count) {
            floor_mid = floor;
        }
    }
    if top - floor_mid < 0.05 {
        return None;
    }
    let side = DVec3::new(-along.y, along.x, 0.0);
    let level = DVec3::new(mid.x, mid.y, top);
    if field.cave(level) > -0.05 || field.water(DVec3::new(mid.x, mid.y, (floor_mid + top) * 0.5)) < 0.0 {
        return None;
    }
    let width = trace(field, level, side, 30.0)?.max(trace(field, level, -side, 30.0)?) + MARGIN;
    let depth = (top - floor_mid) + MARGIN;
    let centre = DVec3::new(mid.x, mid.y, top - depth * 0.5);
    let yaw = along.y.atan2(along.x);
    let round = 0.1;
    let shape = Shape::Block {
        centre: centre.as_vec3().to_array(),
        half: (DVec3::new(length * 0.5, width, depth * 0.5) - round).as_vec3().to_array(),
        rotation: DQuat::from_rotation_z(yaw).as_quat().to_array(),
        round: round as f32,
    };
    Some(Piece { kind: PieceKind::Sediment, shape })
}
