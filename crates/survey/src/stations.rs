//! Where the survey stands: a station every [`SPACING`] metres of arc length along every
//! conduit, from its first node, with the passage's direction there, and the junctions.

use glam::DVec3;

use karst_skeleton::{Conduit, ConduitType, Skeleton, Zone};

/// Distance between stations along a conduit, metres: within the 2.8–5.4 m median leg length
/// of the surveyed caves.
pub const SPACING: f64 = 4.0;

/// A station before it is measured.
#[derive(Debug, Clone, PartialEq)]
pub struct Placed {
    /// Index of the conduit, 0-based.
    pub conduit: usize,
    /// Number along the conduit, from 1.
    pub station: u32,
    /// Arc length from the conduit's first node, metres.
    pub at: f64,
    pub position: DVec3,
    /// Unit direction of the passage (its segment's).
    pub tangent: DVec3,
    pub kind: ConduitType,
    pub zone: Zone,
    /// The skeleton's half-width there: how far to look for an open passage.
    pub radius: f64,
}

/// The stations of every conduit, in conduit order.
pub fn place(skeleton: &Skeleton) -> Vec<Placed> {
    skeleton.conduits.iter().enumerate().flat_map(|(c, conduit)| along(skeleton, c, conduit)).collect()
}

fn along(skeleton: &Skeleton, c: usize, conduit: &Conduit) -> Vec<Placed> {
    let arc = skeleton.arc_lengths(conduit);
    let length = arc[arc.len() - 1];
    let point = |i: usize| DVec3::from_array(skeleton.nodes[conduit.nodes[i] as usize].position);
    let count = (length / SPACING).floor() as u32 + 1;
    (0..count)
        .map(|k| {
            let at = k as f64 * SPACING;
            // The segment holding `at` (the last one for its end).
            let i = arc.partition_point(|s| *s <= at).clamp(1, arc.len() - 1) - 1;
            let (a, b) = (point(i), point(i + 1));
            let t = ((at - arc[i]) / (arc[i + 1] - arc[i])).clamp(0.0, 1.0);
            let nearer = if t < 0.5 { i } else { i + 1 };
            Placed {
                conduit: c,
                station: k + 1,
                at,
                position: a.lerp(b, t),
                tangent: (b - a).normalize(),
                kind: conduit.types[i],
                zone: skeleton.nodes[conduit.nodes[nearer] as usize].zone,
                radius: conduit.passage_at(&arc, at).0,
            }
        })
        .collect()
}

/// Positions of the junctions: nodes where three or more conduit ends meet.
pub fn junctions(skeleton: &Skeleton) -> Vec<DVec3> {
    let mut ends = vec![0u32; skeleton.nodes.len()];
    for conduit in &skeleton.conduits {
        ends[conduit.nodes[0] as usize] += 1;
        ends[conduit.nodes[conduit.nodes.len() - 1] as usize] += 1;
    }
    ends.iter()
        .enumerate()
        .filter(|(_, n)| **n >= 3)
        .map(|(i, _)| DVec3::from_array(skeleton.nodes[i].position))
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use karst_skeleton::Node;

    fn node(x: f64, y: f64) -> Node {
        Node { position: [x, y, 0.0], sample: 0, keypoint: None, zone: Zone::Vadose }
    }

    #[test]
    fn stations_every_four_metres_from_the_first_node_and_junctions_where_three_ends_meet() {
        let conduit = |nodes: Vec<u32>| Conduit {
            radius: vec![1.0; nodes.len()],
            types: vec![ConduitType::Canyon; nodes.len() - 1],
            nodes,
            phase: 0,
            keypoints: Vec::new(),
            profile: Vec::new(),
        };
        let skeleton = Skeleton {
            nodes: vec![node(0.0, 0.0), node(6.0, 0.0), node(10.0, 0.0), node(10.0, 9.0), node(10.0, -3.0)],
            conduits: vec![conduit(vec![0, 1, 2]), conduit(vec![2, 3]), conduit(vec![2, 4])],
            routes: Vec::new(),
            derived: Default::default(),
        };
        let placed = place(&skeleton);
        let first: Vec<f64> = placed.iter().filter(|p| p.conduit == 0).map(|p| p.position[0]).collect();
        assert_eq!(first, [0.0, 4.0, 8.0]);
        let second: Vec<f64> = placed.iter().filter(|p| p.conduit == 1).map(|p| p.position[1]).collect();
        assert_eq!(second, [0.0, 4.0, 8.0]);
        assert_eq!(placed.iter().filter(|p| p.conduit == 2).count(), 1);
        assert_eq!(placed[2].station, 3);
        assert_eq!(placed[2].tangent, DVec3::X);
        assert_eq!(junctions(&skeleton), [DVec3::new(10.0, 0.0, 0.0)]);
    }
}
