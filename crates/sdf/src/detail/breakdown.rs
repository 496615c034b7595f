//! Breakdown: where a passage's roof has collapsed, a chamber stoped upwards with a pile of
//! blocks on its floor.
//!
//! **Why there.** A drained passage loses the buoyant support of its water; its roof then
//! spans as a beam or a plate of bedded limestone whose strength falls with the span and the
//! thinness of the beds above. Breakdown therefore concentrates where spans are widest, at
//! the junctions of large passages, and where a wide passage runs under a thin roof, and
//! stopes upwards, leaving a domed chamber over a pile of fallen blocks (White 1988 ch. 8;
//! Ford & Williams 2007 §7.10). Flooded passages keep their support: only nodes of the vadose
//! zone break down.
//!
//! **The rule.** A vadose node breaks down when the largest radius of the conduits meeting
//! there (times `radius_scale`) is at least `breakdown_radius` and it is a junction (three or
//! more conduit ends) or its roof is thin (overburden above the passage less than twice that
//! radius). The chamber is a dome of three stacked balls over the node (centres 0.2 R, 0.7 R and
//! 1.1 R above it, radii 0.9 R, 0.75 R and 0.5 R; R the largest radius), roughened like every
//! sphere leaf by the chamber type's detail and the wall relief (the noise-walled chamber leaf
//! of crate::tree::chamber is not 1-Lipschitz across its foundation's wall, where its value jumps
//! from the noise's to the foundation's); `breakdown_blocks` blocks lie on the floor
//! within 0.8 R of the node: rounded boxes of edge 0.1 R to 0.5 R (at most 3 m), flattened as
//! bedded slabs are, turned about the vertical at random and tilted by up to 25°, sunk by a
//! third of their thickness into the floor (found by sphere tracing the walls downwards).

use glam::{DQuat, DVec3};
use karst_scene::params::SdfParams;
use karst_scene::rng::Random;
use karst_skeleton::{ConduitType, Skeleton, Zone};

use super::rock::{Piece, PieceKind, Shape};
use super::speleothems::trace;
use crate::field::carved::CarvedTerrain;
use crate::payload::SphereGroup;

/// A node that breaks down: its position and the largest radius meeting there.
pub struct Collapse {
    pub at: DVec3,
    pub radius: f64,
}

/// The nodes that break down, in node order.
pub fn collapses(field: &CarvedTerrain, skeleton: &Skeleton, p: &SdfParams) -> Vec<Collapse> {
    let n = skeleton.nodes.len();
    let mut ends = vec![0u32; n];
    let mut radius = vec![0.0f64; n];
    for conduit in &skeleton.conduits {
        for (k, &node) in conduit.nodes.iter().enumerate() {
            radius[node as usize] = radius[node as usize].max(conduit.radius[k] * p.radius_scale);
        }
        for node in [conduit.nodes.first(), conduit.nodes.last()].into_iter().flatten() {
            ends[*node as usize] += 1;
        }
    }
    (0..n)
        .filter_map(|i| {
            let node = &skeleton.nodes[i];
            let (at, r) = (DVec3::from_array(node.position), radius[i]);
            if node.zone != Zone::Vadose || r < p.breakdown_radius {
                return None;
            }
            let overburden = field.model().terrain.height(at.x, at.y) - (at.z + r);
            (ends[i] >= 3 || (overburden >= 0.0 && overburden < 2.0 * r))
                .then_some(Collapse { at, radius: r })
        })
        .collect()
}

/// The chamber of a collapse, enlarged upwards: a dome of three stacked balls, each with the
/// relief and the chamber type's detail of a sphere leaf.
pub fn chamber(c: &Collapse) -> SphereGroup {
    let ball = |h: f64, r: f64| {
        let at = (c.at + DVec3::Z * h * c.radius).as_vec3();
        [at.x, at.y, at.z, (r * c.radius) as f32]
    };
    SphereGroup { kind: ConduitType::Chamber, spheres: vec![ball(0.2, 0.9), ball(0.7, 0.75), ball(1.1, 0.5)] }
}

/// The blocks on the floor of a collapse, drawn from `random`; none where the floor is not
/// found or lies in water.
pub fn blocks(field: &CarvedTerrain, c: &Collapse, count: u32, random: &mut Random) -> Vec<Piece> {
    let mut out = Vec::new();
    for _ in 0..count {
        let (angle, reach) =
            (random.range(0.0, std::f64::consts::TAU), 0.8 * c.radius * random.uniform().sqrt());
        let edge = (c.radius * random.range(0.1, 0.5)).min(3.0);
        let half = DVec3::new(edge, edge * random.range(0.4, 1.0), edge * random.range(0.2, 0.6)) * 0.5;
        let yaw = random.range(0.0, std::f64::consts::TAU);
        let (tilt, tilt_axis) =
            (random.range(0.0, 25f64.to_radians()), random.range(0.0, std::f64::consts::TAU));
        let from = c.at + DVec3::new(angle.cos(), angle.sin(), 0.0) * reach;
        if field.cave(from) > -0.1 || field.water(from) < 0.0 {
            continue;
        }
        let Some(down) = trace(field, from, -DVec3::Z, 3.0 * c.radius) else { continue };
        let centre = from - DVec3::Z * (down - half.z / 1.5);
        if field.water(centre) < 0.0 {
            continue;
        }
        let axis = DVec3::new(tilt_axis.cos(), tilt_axis.sin(), 0.0);
        let rotation = (DQuat::from_axis_angle(axis, tilt) * DQuat::from_rotation_z(yaw)).normalize();
        let round = 0.15 * half.min_element();
        let shape = Shape::Block {
            centre: centre.as_vec3().to_array(),
            half: (half - round).as_vec3().to_array(),
            rotation: rotation.as_quat().to_array(),
            round: round as f32,
        };
        out.push(Piece { kind: PieceKind::Block, shape });
    }
    out
}
