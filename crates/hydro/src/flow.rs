//! Flow propagation (Emilien et al. 2015 §4.2.1): nodes are solved one by one in dependency
//! order, from the sources to the wells. At a branch node each incoming flow γ_j (a link, or
//! the recharge of a sink, which arrives from above) is split over the outgoing links with
//! the normalized weights w̄_jk of w_jk = 1 + u_j · v_k, u_j the incoming and v_k the outgoing
//! direction, so that water mostly keeps its course; at a pool the inflow is split equally, or
//! by the weights the scene gives its outlets (`[[hydro.pools]]`).
//! A spring takes all the water reaching it. The last outgoing link receives what the others
//! left, so each node gives out exactly what it receives (up to the rounding of one
//! subtraction). Flows are carried per sink, so every spring knows which sinks feed it.

use glam::DVec3;

use karst_scene::params::PoolOutlet;

use crate::graph::{Graph, Terminal};
use crate::orient::Orientation;

/// Flows of every link, per sink.
#[derive(Debug, Clone, PartialEq)]
pub struct Flows {
    /// Number of sinks.
    pub sinks: usize,
    /// `shares[link * sinks + s]`: the water of sink s in the link.
    pub shares: Vec<f64>,
    /// Water reaching each node (recharge included).
    pub inflow: Vec<f64>,
    /// `discharge[spring * sinks + s]`: the water of sink s leaving at each spring.
    pub discharge: Vec<f64>,
}

impl Flows {
    /// Total flow of `link`.
    pub fn link(&self, link: usize) -> f64 {
        self.shares[link * self.sinks..(link + 1) * self.sinks].iter().sum()
    }

    /// The water of sink `sink` leaving at spring `spring`.
    pub fn share(&self, spring: usize, sink: usize) -> f64 {
        self.discharge[spring * self.sinks + sink]
    }
}

/// One incoming flow at a node: its direction and its water per sink.
struct Inflow {
    direction: DVec3,
    shares: Vec<f64>,
}

/// How a node splits each inflow over its outgoing links.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Split<'a> {
    /// Emilien et al.'s w_jk = 1 + u_j·v_k: water mostly keeps its course.
    Directional,
    /// A pool: equal shares.
    Equal,
    /// A pool with user weights (`[[hydro.pools]]`): see [`outlet_weights`].
    User(&'a [PoolOutlet]),
}

/// The user weight of each outgoing direction `out` (unit vectors) of a pool at `at`: the
/// weight of the outlet whose direction from the pool is closest to it (largest cosine, the
/// first listed on a tie).
pub fn outlet_weights(at: DVec3, out: &[DVec3], outlets: &[PoolOutlet]) -> Vec<f64> {
    let towards: Vec<DVec3> =
        outlets.iter().map(|o| (DVec3::from_array(o.towards) - at).normalize_or_zero()).collect();
    out.iter()
        .map(|v| {
            let mut best = (f64::NEG_INFINITY, 0.0);
            for (t, o) in towards.iter().zip(outlets) {
                let cosine = v.dot(*t);
                if cosine > best.0 {
                    best = (cosine, o.weight);
                }
            }
            best.1
        })
        .collect()
}

/// The unit directions of the outgoing links `(link, to)` of `node`.
pub fn out_directions(graph: &Graph, node: u32, outgoing: &[(usize, u32)]) -> Vec<DVec3> {
    outgoing
        .iter()
        .map(|&(_, to)| (graph.positions[to as usize] - graph.positions[node as usize]).normalize_or_zero())
        .collect()
}

/// Propagates the sinks' recharge through the oriented graph. `split(node)` says how a node
/// shares its water.
pub fn propagate<'a>(
    graph: &Graph,
    orientation: &Orientation,
    sinks: &[Terminal],
    springs: &[Terminal],
    split_at: impl Fn(u32) -> Split<'a>,
) -> Flows {
    let s = sinks.len();
    let mut flows = Flows {
        sinks: s,
        shares: vec![0.0; graph.links.len() * s],
        inflow: vec![0.0; graph.positions.len()],
        discharge: vec![0.0; springs.len() * s],
    };
    let directions: Vec<Option<(u32, u32)>> =
        (0..graph.links.len()).map(|l| orientation.direction(graph, l)).collect();
    for &node in &orientation.upstream_first {
        let mut inflows = Vec::new();
        let mut outgoing = Vec::new();
        for &l in &graph.at_node[node as usize] {
            match directions[l] {
                Some((from, to)) if to == node => inflows.push(Inflow {
                    direction: (graph.positions[to as usize] - graph.positions[from as usize])
                        .normalize_or_zero(),
                    shares: flows.shares[l * s..(l + 1) * s].to_vec(),
                }),
                Some((from, to)) if from == node => outgoing.push((l, to)),
                _ => {}
            }
        }
        for (i, sink) in sinks.iter().enumerate().filter(|(_, t)| t.node == node) {
            let mut shares = vec![0.0; s];
            shares[i] = sink.weight;
            inflows.push(Inflow { direction: DVec3::NEG_Z, shares });
        }
        flows.inflow[node as usize] = inflows.iter().flat_map(|f| &f.shares).sum();
        if let Some(w) = springs.iter().position(|t| t.node == node) {
            for f in &inflows {
                for (d, x) in flows.discharge[w * s..(w + 1) * s].iter_mut().zip(&f.shares) {
                    *d += x;
                }
            }
            continue;
        }
        let out = out_directions(graph, node, &outgoing);
        let rule = split_at(node);
        let user = match rule {
            Split::User(outlets) => Some(outlet_weights(graph.positions[node as usize], &out, outlets)),
            _ => None,
        };
        for f in &inflows {
            let weights = split(f.direction, &out, rule, user.as_deref());
            distribute(&mut flows.shares, s, &outgoing, &weights, &f.shares);
        }
    }
    flows
}

/// Normalized weights of one inflow of direction `u` over the outgoing directions `out`
/// (`user`: the user weights of a [`Split::User`] pool).
pub fn split(u: DVec3, out: &[DVec3], rule: Split, user: Option<&[f64]>) -> Vec<f64> {
    let raw: Vec<f64> = match (rule, user) {
        (Split::Directional, _) => out.iter().map(|v| 1.0 + u.dot(*v)).collect(),
        (Split::User(_), Some(user)) => user.to_vec(),
        _ => vec![1.0; out.len()],
    };
    let total: f64 = raw.iter().sum();
    if total > 1e-12 {
        raw.iter().map(|w| w / total).collect()
    } else {
        vec![1.0 / out.len() as f64; out.len()]
    }
}

/// Adds `shares` times `weights` to the outgoing links; the last link takes the remainder.
fn distribute(links: &mut [f64], s: usize, outgoing: &[(usize, u32)], weights: &[f64], shares: &[f64]) {
    for (k, &(l, _)) in outgoing.iter().enumerate() {
        for (i, &x) in shares.iter().enumerate() {
            let given = if k + 1 == outgoing.len() {
                let others: f64 = weights[..k].iter().map(|w| x * w).sum();
                (x - others).max(0.0)
            } else {
                x * weights[k]
            };
            links[l * s + i] += given;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn straight_on_takes_most_and_backwards_takes_nothing() {
        let w = split(DVec3::X, &[DVec3::X, DVec3::Y, DVec3::NEG_X], Split::Directional, None);
        assert_eq!(w, vec![2.0 / 3.0, 1.0 / 3.0, 0.0]);
        assert_eq!(split(DVec3::X, &[DVec3::X, DVec3::Y], Split::Equal, None), vec![0.5, 0.5]);
        assert_eq!(split(DVec3::X, &[DVec3::NEG_X], Split::Directional, None), vec![1.0]);
    }

    #[test]
    fn user_weights_go_to_the_outlet_in_the_closest_direction() {
        let outlets = [
            PoolOutlet { towards: [10.0, 1.0, 0.0], weight: 3.0 },
            PoolOutlet { towards: [0.0, 10.0, -5.0], weight: 1.0 },
        ];
        let out = [DVec3::Y, DVec3::X, DVec3::new(0.7, -0.7, 0.0)];
        let user = outlet_weights(DVec3::ZERO, &out, &outlets);
        assert_eq!(user, vec![1.0, 3.0, 3.0]);
        let w = split(DVec3::NEG_Z, &out, Split::User(&outlets), Some(&user));
        assert_eq!(w, vec![1.0 / 7.0, 3.0 / 7.0, 3.0 / 7.0]);
    }
}
