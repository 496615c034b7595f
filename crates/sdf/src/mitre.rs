//! Mitred joints between the sweeps of a profiled passage: how far each segment's sweep runs
//! on past its nodes so that two straight sweeps meeting at a bend leave no wedge open on the
//! outside of the bend.
//!
//! Two prisms of one section meeting at a node with a bend of angle θ ≤ 90° and each run on
//! past the node by r·tan(θ/2), r the section's reach on the outside of the bend, overlap as an
//! exact mitre: the outer corners of both meet on the bisecting plane, and what each carries
//! past it lies inside the other. Past a right angle the run-on is r itself, which covers the
//! disc of radius r around the node (a joint rounded at the section's size). The reach is
//! taken on the section's control polygon, whose hull holds the curve.
//!
//! At a conduit's end the bend is measured against the other conduit at that node whose
//! passage continues this one most nearly straight (a trunk split at a junction keeps its line;
//! a branch meeting a trunk runs on into it by its own reach); a dead end or a key point alone
//! at its node has no run-on.

use std::collections::HashMap;

use glam::{DVec2, DVec3};

use karst_skeleton::Skeleton;

use crate::tree::section::Section;
use crate::tree::sweep::{SectionSpec, frame};

/// The ends of the conduits at each node: (conduit, which end, the direction leaving the node
/// into the conduit).
pub struct Junctions {
    ends: HashMap<u32, Vec<(usize, End, DVec3)>>,
}

/// A conduit's first or last node.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum End {
    First,
    Last,
}

impl Junctions {
    pub fn of(skeleton: &Skeleton) -> Junctions {
        let mut ends: HashMap<u32, Vec<(usize, End, DVec3)>> = HashMap::new();
        let position = |n: u32| DVec3::from_array(skeleton.nodes[n as usize].position);
        for (c, conduit) in skeleton.conduits.iter().enumerate() {
            let nodes = &conduit.nodes;
            let (Some(&first), Some(&last)) = (nodes.first(), nodes.last()) else { continue };
            if nodes.len() < 2 {
                continue;
            }
            let leaving = |n: u32, next: u32| (position(next) - position(n)).normalize();
            ends.entry(first).or_default().push((c, End::First, leaving(first, nodes[1])));
            ends.entry(last).or_default().push((c, End::Last, leaving(last, nodes[nodes.len() - 2])));
        }
        Junctions { ends }
    }

    /// The flow directions continuing conduit `c` at its ends: [the direction arriving at its
    /// first node, the direction leaving its last node], each from the other conduit at that
    /// node that bends least from it (None when no other conduit ends there).
    pub fn continuations(&self, skeleton: &Skeleton, c: usize) -> [Option<DVec3>; 2] {
        let nodes = &skeleton.conduits[c].nodes;
        [End::First, End::Last].map(|end| {
            let here = self.ends.get(&node_of(nodes, end)?)?;
            let away = here.iter().find(|e| e.0 == c && e.1 == end)?.2;
            here.iter()
                .filter(|e| (e.0, e.1) != (c, end))
                // The other conduit leaves the node along e.2: the straightest continuation
                // points most nearly opposite to this conduit's own way out of the node.
                .min_by(|x, y| x.2.dot(away).total_cmp(&y.2.dot(away)))
                .map(|e| match end {
                    End::First => -e.2,
                    End::Last => e.2,
                })
        })
    }
}

fn node_of(nodes: &[u32], end: End) -> Option<u32> {
    match end {
        End::First => nodes.first().copied(),
        End::Last => nodes.last().copied(),
    }
}

/// The run-on of each segment of a conduit past its [start, end] node, metres: `points` the
/// conduit's nodes, `sections` their sections, `continuations` the flow directions arriving
/// at the first node and leaving the last ([`Junctions::continuations`]).
pub fn run_ons(
    points: &[DVec3],
    sections: &[SectionSpec],
    continuations: [Option<DVec3>; 2],
) -> Vec<[f64; 2]> {
    let ways: Vec<DVec3> = points.windows(2).map(|w| (w[1] - w[0]).normalize()).collect();
    let n = ways.len();
    let mut out = vec![[0.0; 2]; n];
    for (i, section) in sections.iter().enumerate().take(n + 1) {
        let arriving = if i == 0 { continuations[0] } else { Some(ways[i - 1]) };
        let leaving = if i == n { continuations[1] } else { Some(ways[i]) };
        let (Some(arriving), Some(leaving)) = (arriving, leaving) else { continue };
        let cos = arriving.dot(leaving);
        // The outside of the bend: for the leg arriving, away from the way the next leaves;
        // for the leg leaving, towards the way the previous came from.
        let section = section.section();
        if i > 0 {
            out[i - 1][1] = run_on(&section, arriving, arriving * cos - leaving, cos);
        }
        if i < n {
            out[i][0] = run_on(&section, leaving, arriving - leaving * cos, cos);
        }
    }
    out
}

/// The run-on of a sweep along `axis` (its flow direction) at a bend of cosine `cos` whose
/// outside lies along `outside` (across the axis, not normalized).
fn run_on(section: &Section, axis: DVec3, outside: DVec3, cos: f64) -> f64 {
    if outside.length_squared() < 1e-18 {
        return 0.0;
    }
    // The sweep's frame: x to the right looking along the axis, y up.
    let (right, up) = frame(axis);
    let outside = outside.normalize();
    let reach = section.reach(DVec2::new(outside.dot(right), outside.dot(up))).max(0.0);
    // Past a right angle, the reach itself.
    let half_bend = cos.clamp(0.0, 1.0).acos() / 2.0;
    reach * half_bend.tan()
}

#[cfg(test)]
mod tests {
    use super::*;
    use karst_skeleton::ConduitType;

    use crate::tree::section::Shape;

    fn tube(radius: f32, ratio: f32) -> SectionSpec {
        SectionSpec { kinds: [ConduitType::Tube; 2], shape: Shape { radius, ratio, asymmetry: 0.0 } }
    }

    fn square(half: f32) -> SectionSpec {
        tube(half, 1.0)
    }

    #[test]
    fn a_straight_conduit_runs_on_nowhere() {
        let points = [DVec3::ZERO, DVec3::X * 10.0, DVec3::X * 20.0];
        let sections = [square(1.0); 3];
        assert_eq!(run_ons(&points, &sections, [None, None]), vec![[0.0; 2]; 2]);
        let straight_on = [Some(DVec3::X), Some(DVec3::X)];
        assert_eq!(run_ons(&points, &sections, straight_on), vec![[0.0; 2]; 2]);
    }

    #[test]
    fn a_bend_runs_both_legs_on_by_the_mitre_and_a_sharp_one_by_the_reach() {
        let reach = square(2.0).section().reach(DVec2::X);
        for (degrees, expected) in
            [(30.0_f64, reach * 15f64.to_radians().tan()), (90.0, reach), (150.0, reach)]
        {
            let turn = degrees.to_radians();
            let points = [
                DVec3::ZERO,
                DVec3::X * 10.0,
                DVec3::X * 10.0 + DVec3::new(turn.cos(), turn.sin(), 0.0) * 10.0,
            ];
            let runs = run_ons(&points, &[square(2.0); 3], [None, None]);
            assert_eq!(runs[0][0], 0.0);
            assert_eq!(runs[1][1], 0.0);
            assert!((runs[0][1] - expected).abs() < 1e-9, "{degrees}°: {runs:?} vs {expected}");
            assert!((runs[1][0] - expected).abs() < 1e-9, "{degrees}°: {runs:?} vs {expected}");
        }
    }

    #[test]
    fn a_flat_passage_bending_down_runs_on_by_its_half_height_not_its_half_width() {
        let bed = tube(4.0, 0.25);
        let down = 20f64.to_radians();
        let points =
            [DVec3::ZERO, DVec3::X * 10.0, DVec3::X * 10.0 + DVec3::new(down.cos(), 0.0, -down.sin()) * 10.0];
        let runs = run_ons(&points, &[bed; 3], [None, None]);
        let section = bed.section();
        let half_height = section.reach(DVec2::Y).max(section.reach(-DVec2::Y));
        assert!(runs[0][1] > 0.0 && runs[0][1] <= half_height * 10f64.to_radians().tan() + 1e-9, "{runs:?}");
    }
}
