//! Flows along the conduits, from the sinks' routes.

use std::collections::HashMap;

use serde::{Deserialize, Serialize};

use karst_artifact::{Kind, Payload};
use karst_skeleton::Skeleton;

/// Flow through one conduit (same index as in the skeleton).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct ConduitFlow {
    /// Flow, in the sinks' weight units; ≥ 0.
    pub flow: f64,
    /// True when water runs from the conduit's first node to its last, false when it runs
    /// the other way (meaningless for a dry conduit).
    pub downstream: bool,
    /// No route uses the conduit.
    pub dry: bool,
}

/// Water entering at a sink or leaving at a spring.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Outlet {
    pub name: String,
    pub flow: f64,
}

/// The hydro artifact.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Hydro {
    pub conduits: Vec<ConduitFlow>,
    /// Recharge of each sink, in routing order.
    pub sinks: Vec<Outlet>,
    /// Discharge of each spring.
    pub springs: Vec<Outlet>,
}

impl Payload for Hydro {
    const KIND: Kind = Kind::Hydro;
    const SCHEMA: u32 = 1;
}

/// Flows of every conduit of `skeleton`.
///
/// A route enters a conduit at one end and runs through it (its interior nodes have degree
/// 2), so it crosses the conduit's first link exactly once: that link's crossings, signed by
/// direction and weighted, give the conduit's net flow.
pub fn compute(skeleton: &Skeleton) -> Hydro {
    let first_links: HashMap<(u32, u32), usize> = skeleton
        .conduits
        .iter()
        .enumerate()
        .filter(|(_, c)| c.nodes.len() >= 2)
        .map(|(i, c)| ((c.nodes[0], c.nodes[1]), i))
        .collect();
    let mut net = vec![0.0f64; skeleton.conduits.len()];
    let mut used = vec![false; skeleton.conduits.len()];
    for route in &skeleton.routes {
        for w in route.nodes.windows(2) {
            if let Some(&c) = first_links.get(&(w[0], w[1])) {
                net[c] += route.weight;
                used[c] = true;
            } else if let Some(&c) = first_links.get(&(w[1], w[0])) {
                net[c] -= route.weight;
                used[c] = true;
            }
        }
    }
    let conduits = net
        .iter()
        .zip(&used)
        .map(|(&f, &u)| ConduitFlow { flow: f.abs(), downstream: f >= 0.0, dry: !u })
        .collect();
    Hydro {
        conduits,
        sinks: totals(skeleton.routes.iter().map(|r| (&r.sink, r.weight))),
        springs: totals(skeleton.routes.iter().map(|r| (&r.spring, r.weight))),
    }
}

/// Sums of weights per name, in order of first appearance.
fn totals<'a>(items: impl Iterator<Item = (&'a String, f64)>) -> Vec<Outlet> {
    let mut out: Vec<Outlet> = Vec::new();
    for (name, w) in items {
        match out.iter_mut().find(|o| &o.name == name) {
            Some(o) => o.flow += w,
            None => out.push(Outlet { name: name.clone(), flow: w }),
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use karst_skeleton::{Conduit, ConduitType, Node, Route, Zone};

    fn node(x: f64) -> Node {
        Node { position: [x, 0.0, 0.0], sample: x as u32, keypoint: None, zone: Zone::Vadose }
    }

    fn route(sink: &str, weight: f64, nodes: &[u32]) -> Route {
        Route { sink: sink.into(), spring: "S".into(), weight, nodes: nodes.to_vec(), cost: 0.0 }
    }

    /// Net inflow minus outflow at every node, sources and springs included.
    fn imbalance(s: &Skeleton, h: &Hydro) -> Vec<f64> {
        let mut balance = vec![0.0; s.nodes.len()];
        for (c, f) in s.conduits.iter().zip(&h.conduits) {
            let (from, to) = if f.downstream {
                (c.nodes[0], *c.nodes.last().unwrap())
            } else {
                (*c.nodes.last().unwrap(), c.nodes[0])
            };
            balance[from as usize] -= f.flow;
            balance[to as usize] += f.flow;
        }
        for r in &s.routes {
            balance[r.nodes[0] as usize] += r.weight;
            balance[*r.nodes.last().unwrap() as usize] -= r.weight;
        }
        balance
    }

    #[test]
    fn confluence_adds_flows_and_conserves_them() {
        // Sinks at 0 and 1 join at 2 and drain to 3; conduit 3 (2–4) is a dry dead end.
        let skeleton = Skeleton {
            nodes: (0..5).map(|i| node(i as f64)).collect(),
            conduits: vec![
                Conduit {
                    nodes: vec![0, 2],
                    radius: vec![1.0; 2],
                    types: vec![ConduitType::Canyon],
                    phase: 0,
                    keypoints: vec![],
                },
                Conduit {
                    nodes: vec![2, 1],
                    radius: vec![1.0; 2],
                    types: vec![ConduitType::Canyon],
                    phase: 0,
                    keypoints: vec![],
                },
                Conduit {
                    nodes: vec![2, 3],
                    radius: vec![1.0; 2],
                    types: vec![ConduitType::Canyon],
                    phase: 0,
                    keypoints: vec![],
                },
                Conduit {
                    nodes: vec![2, 4],
                    radius: vec![1.0; 2],
                    types: vec![ConduitType::Canyon],
                    phase: 0,
                    keypoints: vec![],
                },
            ],
            routes: vec![route("a", 1.5, &[0, 2, 3]), route("b", 2.0, &[1, 2, 3])],
        };
        let h = compute(&skeleton);
        assert_eq!(h.conduits[2], ConduitFlow { flow: 3.5, downstream: true, dry: false });
        assert_eq!(h.conduits[1], ConduitFlow { flow: 2.0, downstream: false, dry: false });
        assert!(h.conduits[3].dry);
        assert_eq!(h.springs, vec![Outlet { name: "S".into(), flow: 3.5 }]);
        assert!(imbalance(&skeleton, &h).iter().all(|b| b.abs() < 1e-12));
    }
}
