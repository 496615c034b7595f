//! Tortuosity (Paris et al. 2021 §5.2): every link of the network is refined by stochastic
//! midpoint displacement. At level 1 the midpoint of each segment moves by a random offset of
//! up to A = 0.05 m + θ · 3.95 m (θ = `skeleton.tortuosity`: a few centimetres at 0, 4 m at
//! 1); each further level (`skeleton.tortuosity_levels`) halves A on the new halves. An offset
//! that would leave the bedrock is drawn again (up to 8 times), then dropped: the node stays at
//! the midpoint.
//!
//! The offset is not white noise in every direction: a passage develops along a plane of
//! weakness, so the midpoint moves across the segment within the weakness plane the segment
//! lies in (`planes.rs`): along a fracture it follows, else the bedding. Conduits wander
//! sideways along their parting, not up and down through the beds.
//!
//! New nodes carry the sample of the nearer end of their link. Routes are rewritten through the
//! new nodes, so flows follow the tortuous conduits.

use std::collections::BTreeMap;

use glam::DVec3;
use karst_scene::rng::Random;

use crate::network::nodes::node_at;
use crate::network::shape::planes::WeaknessPlanes;
use crate::payload::{Node, Route};
use crate::view::SkeletonView;

/// Draws per displaced midpoint before it stays straight.
const TRIES: usize = 8;

/// The nodes inserted into links, keyed by the link (a, b), a < b, in the order from a to b.
pub type Insertions = BTreeMap<(u32, u32), Vec<u32>>;

/// Displacement amplitude of the first level for θ, metres.
pub fn amplitude(theta: f64) -> f64 {
    0.05 + theta * 3.95
}

/// Refines `chains` in place, appending the new nodes to `nodes`; returns the insertions.
pub fn refine(view: &SkeletonView, theta: f64, nodes: &mut Vec<Node>, chains: &mut [Vec<u32>]) -> Insertions {
    let mut rng = Random::stream(view.seed, "skeleton", "tortuosity");
    let levels = view.skeleton.tortuosity_levels;
    let planes = WeaknessPlanes::of(&karst_costgraph::fracture_families(&view.costs()));
    let mut inserted = Insertions::new();
    for chain in chains.iter_mut() {
        let mut refined = vec![chain[0]];
        for w in chain.windows(2) {
            let (a, b) = (w[0], w[1]);
            let pa = DVec3::from_array(nodes[a as usize].position);
            let pb = DVec3::from_array(nodes[b as usize].position);
            let mut points = vec![pa, pb];
            for level in 0..levels {
                let reach = amplitude(theta) / f64::from(1u32 << level);
                points = subdivide(view, &planes, &mut rng, &points, reach);
            }
            let interior = &points[1..points.len() - 1];
            let half = interior.len() / 2;
            let ids: Vec<u32> = interior
                .iter()
                .enumerate()
                .map(|(i, p)| {
                    let sample = nodes[if i < half { a } else { b } as usize].sample;
                    nodes.push(node_at(view.geology, p.to_array(), sample, None));
                    (nodes.len() - 1) as u32
                })
                .collect();
            refined.extend(&ids);
            refined.push(b);
            let forward = if a < b { ids } else { ids.into_iter().rev().collect() };
            inserted.insert((a.min(b), a.max(b)), forward);
        }
        *chain = refined;
    }
    inserted
}

/// Rewrites `routes` through the nodes inserted into their links.
pub fn reroute(routes: &mut [Route], inserted: &Insertions) {
    for route in routes {
        let mut nodes_of_route = vec![route.nodes[0]];
        for w in route.nodes.windows(2) {
            let (a, b) = (w[0], w[1]);
            if let Some(ids) = inserted.get(&(a.min(b), a.max(b))) {
                if a < b {
                    nodes_of_route.extend(ids);
                } else {
                    nodes_of_route.extend(ids.iter().rev());
                }
            }
            nodes_of_route.push(b);
        }
        route.nodes = nodes_of_route;
    }
}

/// One level: a displaced midpoint between every two consecutive points.
fn subdivide(
    view: &SkeletonView,
    planes: &WeaknessPlanes,
    rng: &mut Random,
    points: &[DVec3],
    reach: f64,
) -> Vec<DVec3> {
    let mut out = vec![points[0]];
    for w in points.windows(2) {
        let mid = (w[0] + w[1]) * 0.5;
        let across = planes.across(view.geology, mid, w[1] - w[0]);
        let displaced = (0..TRIES).find_map(|_| {
            let p = mid + across * rng.range(-reach, reach);
            view.in_bedrock(p).then_some(p)
        });
        out.push(displaced.unwrap_or(mid));
        out.push(w[1]);
    }
    out
}
