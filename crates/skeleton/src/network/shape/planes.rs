//! Planes of weakness: the bedding and the fracture families, along which passages develop.
//! Conduits bend within them (meanders, midpoint displacement) rather than in every direction.
//!
//! A segment lies in a fracture family's plane when the angle between them is within the
//! family's tolerance: the passage formed along that fracture (the cost model made it follow
//! it), so it bends within it — up and down along a steep joint, as phreatic loops do. A
//! segment at the intersection of several families (a joint and a bedding-parallel parting)
//! bends in the steepest: the joint carries the loops (Ford & Ewers 1978), and the passage
//! keeps the azimuth of the joint set, as in the rectilinear mazes of jointed rock. Any
//! other segment bends in the plane it lies in best among the bedding and the fractures: for
//! the gently sloping passages of most caves, the bedding plane, where vadose streams meander.
//! The bedding is the plane of the nearest inception horizon, horizontal when the scene has
//! none.

use glam::DVec3;
use karst_geology::{FractureFamily, Geology};

/// The fracture families' planes of a scene.
pub struct WeaknessPlanes {
    /// Unit normal and sine of the angular tolerance of each fracture family.
    fractures: Vec<(DVec3, f64)>,
}

impl WeaknessPlanes {
    /// The planes of `families`: the scene's fracture families, or the joint sets the cost
    /// model assumes without them ([`karst_costgraph::fracture_families`]), so that a passage the
    /// costs made follow a joint bends within it either way.
    pub fn of(families: &[FractureFamily]) -> Self {
        let fractures = families.iter().map(|f| (f.normal(), f.tolerance.to_radians().sin())).collect();
        WeaknessPlanes { fractures }
    }

    /// The unit direction across `segment` (at `at`) within the weakness plane it lies in.
    pub fn across(&self, geology: &Geology, at: DVec3, segment: DVec3) -> DVec3 {
        let axis = segment.normalize_or_zero();
        if axis == DVec3::ZERO {
            return DVec3::X;
        }
        let off = |n: &DVec3| n.dot(axis).abs();
        let along_fracture = self
            .fractures
            .iter()
            .filter(|(n, sin_tolerance)| off(n) <= *sin_tolerance)
            .map(|(n, _)| *n)
            .min_by(|a, b| a.z.abs().total_cmp(&b.z.abs()).then(off(a).total_cmp(&off(b))));
        let normal = along_fracture.unwrap_or_else(|| {
            self.fractures
                .iter()
                .map(|(n, _)| *n)
                .chain([bedding_normal(geology, at)])
                .min_by(|a, b| off(a).total_cmp(&off(b)))
                .expect("the bedding is always a plane")
        });
        let across = normal.cross(axis).normalize_or_zero();
        if across == DVec3::ZERO { axis.any_orthonormal_vector() } else { across }
    }
}

/// The upward normal of the bedding at `p`: the nearest inception horizon's, vertical when the
/// scene has none.
pub fn bedding_normal(geology: &Geology, p: DVec3) -> DVec3 {
    geology
        .horizons
        .iter()
        .min_by(|a, b| a.distance(p).total_cmp(&b.distance(p)))
        .map_or(DVec3::Z, |h| h.normal())
}

#[cfg(test)]
mod tests {
    use super::*;

    const JOINTED: &str = r#"
name = "jointed"
seed = 1
[domain]
min = [0, 0, 0]
max = [100, 100, 50]
[terrain]
kind = "plane"
elevation = 48
# Partings first: the steepest family wins whatever the order.
[[geology.fractures]]
name = "partings"
azimuth = 0.0
dip = 0.0
tolerance = 10.0
[[geology.fractures]]
name = "north-south joints"
azimuth = 0.0
dip = 90.0
tolerance = 10.0
[[geology.water_tables]]
name = "base"
elevation = 10
[[keypoints]]
name = "in"
kind = "sink"
position = [10, 10, 45]
[[keypoints]]
name = "out"
kind = "spring"
position = [90, 90, 10]
water_table = "base"
"#;

    #[test]
    fn a_passage_along_a_joint_and_a_parting_bends_in_the_joint() {
        let scene = karst_scene::Scene::parse(JOINTED, std::path::Path::new("jointed.toml")).unwrap();
        let planes = WeaknessPlanes::of(&scene.geology().fractures);
        let at = DVec3::new(50.0, 50.0, 20.0);
        // North–south and level: in both families; the joint (vertical) carries the bends.
        let across = planes.across(scene.geology(), at, DVec3::Y);
        assert!(across.z.abs() > 0.99, "{across}");
        // North-east and level: only in the parting; it bends sideways, level.
        let across = planes.across(scene.geology(), at, DVec3::new(1.0, 1.0, 0.0));
        assert!(across.z.abs() < 1e-9 && across.dot(DVec3::new(1.0, 1.0, 0.0)).abs() < 1e-9, "{across}");
    }
}
