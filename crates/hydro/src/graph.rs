//! The hydraulic graph of a skeleton (Emilien et al. 2015 §4.2): every segment of every
//! conduit is a link between two nodes; sinks are its sources and springs its wells. Built
//! only from the skeleton's nodes, conduits and routes, so dead ends, loops and relict
//! conduits are links like any other.

use glam::DVec3;

use karst_skeleton::Skeleton;

use crate::HydroError;

/// One segment `conduits[conduit].nodes[segment] → nodes[segment + 1]`, as a link a – b.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Link {
    pub a: u32,
    pub b: u32,
    pub conduit: usize,
    pub segment: usize,
}

/// A sink (with its recharge) or a spring, at a node.
#[derive(Debug, Clone, PartialEq)]
pub struct Terminal {
    pub name: String,
    pub node: u32,
    /// Recharge of a sink; 0 for a spring.
    pub weight: f64,
}

/// The links of a skeleton and the links at each node.
#[derive(Debug, Clone)]
pub struct Graph {
    pub positions: Vec<DVec3>,
    pub links: Vec<Link>,
    /// Indices into `links`, per node, in conduit order.
    pub at_node: Vec<Vec<usize>>,
}

impl Graph {
    /// The graph of `skeleton` (checked by `Skeleton::validate`: nodes exist, positions are
    /// finite, one radius per node).
    pub fn of(skeleton: &Skeleton) -> Graph {
        let positions: Vec<DVec3> = skeleton.nodes.iter().map(|n| DVec3::from_array(n.position)).collect();
        let mut links = Vec::new();
        let mut at_node = vec![Vec::new(); skeleton.nodes.len()];
        for (c, conduit) in skeleton.conduits.iter().enumerate() {
            for (segment, w) in conduit.nodes.windows(2).enumerate() {
                at_node[w[0] as usize].push(links.len());
                if w[1] != w[0] {
                    at_node[w[1] as usize].push(links.len());
                }
                links.push(Link { a: w[0], b: w[1], conduit: c, segment });
            }
        }
        Graph { positions, links, at_node }
    }

    /// The other end of link `l` seen from `node`.
    pub fn across(&self, l: usize, node: u32) -> u32 {
        let link = &self.links[l];
        if link.a == node { link.b } else { link.a }
    }

    /// Length of link `l`, metres.
    pub fn length(&self, l: usize) -> f64 {
        let link = &self.links[l];
        self.positions[link.a as usize].distance(self.positions[link.b as usize])
    }
}

/// The sinks of `skeleton`'s routes, once each in order of first route, with their weights
/// (`weight` overrides a sink's route weight when it returns a value). Routes are not empty
/// and their weights finite and ≥ 0 (`Skeleton::validate`); so are the scene's.
pub fn sinks(skeleton: &Skeleton, weight: impl Fn(&str) -> Option<f64>) -> Vec<Terminal> {
    let mut out: Vec<Terminal> = Vec::new();
    for route in &skeleton.routes {
        if out.iter().any(|t| t.name == route.sink) {
            continue;
        }
        let node = route.nodes[0];
        let w = weight(&route.sink).unwrap_or(route.weight);
        out.push(Terminal { name: route.sink.clone(), node, weight: w });
    }
    out
}

/// The springs: the ends of the routes, then the nodes whose key point is in `spring_names`,
/// once each.
pub fn springs(skeleton: &Skeleton, spring_names: &[String]) -> Result<Vec<Terminal>, HydroError> {
    let mut out: Vec<Terminal> = Vec::new();
    let mut add = |name: &str, node: u32| {
        if !out.iter().any(|t| t.name == name) {
            out.push(Terminal { name: name.to_string(), node, weight: 0.0 });
        }
    };
    for route in &skeleton.routes {
        if let Some(&node) = route.nodes.last() {
            add(&route.spring, node);
        }
    }
    for (i, node) in skeleton.nodes.iter().enumerate() {
        if let Some(name) = node.keypoint.as_ref().filter(|k| spring_names.contains(k)) {
            add(name, i as u32);
        }
    }
    if out.is_empty() {
        return Err(HydroError::NoSpring);
    }
    Ok(out)
}
