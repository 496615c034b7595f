//! Classification of conduit segments into the tunnel types of Paris et al. 2021 §5.3 (Fig. 11),
//! from the segment's verticality and its height above the water table:
//!
//! - steeper than `skeleton.vertical_angle`: a shaft; `epikarst` when it starts within
//!   `skeleton.epikarst_depth` of the ground, `tube` below;
//! - at or below the water table: `bed` (phreatic conduits);
//! - inclined between half the vertical angle and the vertical angle: `passage`;
//! - gently sloping within `skeleton.keyhole_height` above the water table: `keyhole`
//!   (a vadose canyon cut into a phreatic tube);
//! - gently sloping higher up: `canyon`.
//!
//! Before all of these, a segment whose midpoint lies in ghost rock is a `chamber`: the
//! karstification potential there reaches `skeleton.ghost_rock_potential` (Paris et al.'s
//! resistance π ≈ 0, KarstNSim's potential ≈ 1). Without that threshold there are no chambers.

use glam::DVec3;

use crate::payload::ConduitType;
use crate::view::SkeletonView;

/// The type of the segment a → b.
pub fn classify(view: &SkeletonView, a: DVec3, b: DVec3) -> ConduitType {
    let p = view.skeleton;
    let d = b - a;
    let length = d.length();
    let dip = if length > 0.0 { (d.z.abs() / length).asin().to_degrees() } else { 0.0 };
    let top = if a.z >= b.z { a } else { b };
    let mid = (a + b) * 0.5;
    if p.ghost_rock_potential.is_some_and(|g| view.geology.potential(mid) >= g) {
        return ConduitType::Chamber;
    }
    let above_water = view.geology.water_tables.iter().map(|w| w.height_above(mid)).reduce(f64::min);
    if dip >= p.vertical_angle {
        let depth = view.terrain.height(top.x, top.y) - top.z;
        return if depth <= p.epikarst_depth { ConduitType::Epikarst } else { ConduitType::Tube };
    }
    match above_water {
        Some(h) if h <= 0.0 => ConduitType::Bed,
        _ if dip >= p.vertical_angle * 0.5 => ConduitType::Passage,
        Some(h) if h <= p.keyhole_height => ConduitType::Keyhole,
        _ => ConduitType::Canyon,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use karst_scene::{Scene, SceneView};
    use std::path::Path;

    fn scene() -> Scene {
        let text = r#"
name = "c"
[domain]
min = [0, 0, 0]
max = [100, 100, 100]
[terrain]
kind = "plane"
elevation = 90
[[geology.water_tables]]
name = "w"
elevation = 30
[[keypoints]]
name = "a"
kind = "sink"
position = [1, 1, 90]
[[keypoints]]
name = "s"
kind = "spring"
position = [99, 99, 30]
water_table = "w"
"#;
        Scene::parse(text, Path::new("c.toml")).unwrap()
    }

    #[test]
    fn types_follow_verticality_and_the_water_table() {
        let s = scene();
        let view = SkeletonView::of(&s);
        let v = |x: f64, y: f64, z: f64| DVec3::new(x, y, z);
        assert_eq!(classify(&view, v(10.0, 10.0, 88.0), v(10.0, 11.0, 70.0)), ConduitType::Epikarst);
        assert_eq!(classify(&view, v(10.0, 10.0, 60.0), v(10.0, 11.0, 45.0)), ConduitType::Tube);
        assert_eq!(classify(&view, v(10.0, 10.0, 60.0), v(30.0, 10.0, 58.0)), ConduitType::Canyon);
        assert_eq!(classify(&view, v(10.0, 10.0, 35.0), v(30.0, 10.0, 34.0)), ConduitType::Keyhole);
        assert_eq!(classify(&view, v(10.0, 10.0, 60.0), v(20.0, 10.0, 52.0)), ConduitType::Passage);
        assert_eq!(classify(&view, v(10.0, 10.0, 25.0), v(30.0, 10.0, 24.0)), ConduitType::Bed);
    }

    #[test]
    fn ghost_rock_makes_chambers() {
        let mut s = scene();
        let v = |x: f64, y: f64, z: f64| DVec3::new(x, y, z);
        s.skeleton_mut().ghost_rock_potential = Some(1.0);
        assert_eq!(
            classify(&SkeletonView::of(&s), v(10.0, 10.0, 60.0), v(30.0, 10.0, 58.0)),
            ConduitType::Chamber
        );
    }
}
