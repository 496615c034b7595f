//! Flows on the surface graph (Emilien et al. 2015 §4.2.1), solved node by node from the
//! sources to the wells, with the hydro stage's splitting rule ([`karst_hydro::split`]):
//! at a branch each incoming flow (a segment, or the water entering at the node, which comes
//! from above) is shared over the outgoing segments by w = 1 + u·v, normalised; a pool shares
//! its inflow equally among its outlets. The last outgoing segment takes what the others
//! left, so every node gives out what it receives.

use std::collections::VecDeque;

use glam::DVec3;

use karst_hydro::{Split, split};

use crate::network::Network;
use crate::payload::Role;

/// The flow of every edge and the inflow of every node, m³/s; `None` when the graph has a
/// loop (which tracing never makes).
pub fn propagate(net: &Network, lateral: &[f64]) -> Option<(Vec<f64>, Vec<f64>)> {
    let n = net.positions.len();
    let mut flow = vec![0.0; net.edges.len()];
    let mut inflow = vec![0.0; n];
    let mut waiting: Vec<usize> = net.into.iter().map(Vec::len).collect();
    let mut ready: VecDeque<usize> = (0..n).filter(|&i| waiting[i] == 0).collect();
    let mut solved = 0;
    while let Some(node) = ready.pop_front() {
        solved += 1;
        let mut parts: Vec<(DVec3, f64)> = net.into[node]
            .iter()
            .map(|&e| {
                let edge = &net.edges[e as usize];
                (direction(net, edge.from, edge.to), flow[e as usize])
            })
            .collect();
        parts.push((DVec3::NEG_Z, net.source[node] + lateral[node]));
        inflow[node] = parts.iter().map(|p| p.1).sum();
        let outgoing = &net.out[node];
        if !outgoing.is_empty() {
            let out: Vec<DVec3> =
                outgoing.iter().map(|&e| direction(net, node as u32, net.edges[e as usize].to)).collect();
            let rule = if net.roles[node] == Role::Pool { Split::Equal } else { Split::Directional };
            for (u, q) in parts {
                let weights = split(u, &out, rule, None);
                let mut given = 0.0;
                for (k, &e) in outgoing.iter().enumerate() {
                    let share = if k + 1 == outgoing.len() { (q - given).max(0.0) } else { q * weights[k] };
                    given += share;
                    flow[e as usize] += share;
                }
            }
        }
        for &e in outgoing {
            let to = net.edges[e as usize].to as usize;
            waiting[to] -= 1;
            if waiting[to] == 0 {
                ready.push_back(to);
            }
        }
    }
    (solved == n).then_some((flow, inflow))
}

fn direction(net: &Network, from: u32, to: u32) -> DVec3 {
    (net.positions[to as usize] - net.positions[from as usize]).normalize_or_zero()
}
