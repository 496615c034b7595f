//! The streams stage's entry: the springs' mouths, the controller curves, the traced
//! trajectories, then flows, types and geometry of every segment (see the crate's docs for the
//! method and the modules that do each part).

use glam::DVec3;

use karst_hydro::Hydro;
use karst_scene::{KeyPointKind, keypoints_of};

use crate::error::StreamsError;
use crate::ground::{Grid, Ground};
use crate::network::Network;
use crate::payload::{Node, Outline, Pool, Role, Segment, SpringMouth, Streams};
use crate::trace::{Tracer, Velocity};
use crate::view::StreamsView;
use crate::{catchment, curves, flow, mouth, water};

/// The surface network of `scene`, fed by the springs of `hydro`.
pub fn build(view: &StreamsView, hydro: &Hydro) -> Result<Streams, StreamsError> {
    let params = view.streams;
    let ground = Ground { terrain: view.terrain, domain: *view.domain, probe: 0.5 * params.step };
    let grid = Grid::of(&ground, params.catchment_cell);
    if let Some(c) = grid.heights.iter().position(|h| !h.is_finite()) {
        let p = grid.centre(c);
        return Err(StreamsError::Terrain { x: p.x, y: p.y, height: grid.heights[c] });
    }
    let discharges = discharges(view, hydro)?;
    let mut net = Network::new(params.step);
    let mut springs = Vec::new();
    let mut starts = Vec::new();
    for (name, position, discharge) in discharges {
        let found = match mouth::find(&ground, position, 0.5 * params.catchment_cell) {
            mouth::Daylight::Mouth(m) => Some(m),
            mouth::Daylight::Side(p) => {
                net.reports.push(format!(
                    "spring \"{name}\": the domain's side at [{:.1}, {:.1}, {:.1}] is nearer than any ground; its \
                     water ({discharge:.4} m³/s) leaves the domain there",
                    p.x, p.y, p.z
                ));
                None
            }
        };
        let node = found.map(|m| {
            let node = net.add_node(m.point, Role::Source);
            net.source[node as usize] = discharge;
            starts.push((node, m.direction, name.clone()));
            node
        });
        springs.push(SpringMouth {
            name,
            position: position.to_array(),
            mouth: found.map(|m| m.point.to_array()),
            node,
            discharge,
        });
    }
    let laid = curves::lay(params, &ground, &mut net, &starts);
    let mut tracer = Tracer::new(&ground, &grid, params, &mut net);
    for (node, direction, name) in &starts {
        if laid.captured.contains(node) {
            continue;
        }
        let v = Velocity { direction: *direction, horizontal: params.mouth_speed, vertical: 0.0 };
        tracer.trace(*node, Some(v), &format!("spring \"{name}\""));
    }
    for end in &laid.ends {
        match end {
            curves::End::Trace { node, name } => tracer.trace(*node, None, &format!("curve \"{name}\"")),
            curves::End::Land { edge, name } => tracer.land(*edge, &format!("curve \"{name}\"")),
            curves::End::Spill { pool, outlet, level, name } => {
                tracer.spill(*pool, *outlet, *level, &format!("curve \"{name}\""))
            }
        }
    }
    let lateral = catchment::lateral(&grid, &net, params.runoff);
    let (flow, inflow) = flow::propagate(&net, &lateral).ok_or(StreamsError::Loop)?;
    let mut reports = std::mem::take(&mut net.reports);
    let mut segments = water::segments(&net, &flow, params, &mut reports);
    for (s, e) in segments.iter_mut().zip(&net.edges) {
        s.curve = e.curve.map(|c| params.curves[c].name.clone());
    }
    let pools = pools(&net, &segments);
    let nodes = (0..net.positions.len())
        .map(|n| Node {
            position: net.positions[n].to_array(),
            role: net.roles[n],
            source: net.source[n],
            lateral: lateral[n],
            inflow: inflow[n],
        })
        .collect();
    Ok(Streams { flow_range: params.flow_range, nodes, segments, pools, springs, reports })
}

/// Each scene spring with its key point and its discharge in m³/s: the hydro stage's spring
/// flow times `hydro.total_discharge` over the total flow of the springs.
fn discharges(view: &StreamsView, hydro: &Hydro) -> Result<Vec<(String, DVec3, f64)>, StreamsError> {
    for s in &hydro.springs {
        if keypoints_of(view.keypoints, KeyPointKind::Spring).all(|(_, k)| k.name != s.name) {
            return Err(StreamsError::UnknownSpring(s.name.clone()));
        }
        if !(s.flow.is_finite() && s.flow >= 0.0) {
            return Err(StreamsError::BadFlow { name: s.name.clone(), flow: s.flow });
        }
    }
    let total: f64 = hydro.springs.iter().map(|s| s.flow).sum();
    let scale = if total > 0.0 { view.total_discharge / total } else { 0.0 };
    Ok(keypoints_of(view.keypoints, KeyPointKind::Spring)
        .map(|(_, k)| {
            let flow = hydro.springs.iter().find(|s| s.name == k.name).map_or(0.0, |s| s.flow);
            (k.name.clone(), k.point(), flow * scale)
        })
        .collect())
}

/// The pools, with the depth a plunge pool digs.
fn pools(net: &Network, segments: &[Segment]) -> Vec<Pool> {
    net.pools
        .iter()
        .map(|p| {
            let mut depth = p.depth;
            if let (Some(f), Outline::Disc { radius, .. }) = (p.fall, &p.outline) {
                let s = &segments[f as usize];
                let drop = s.fall.as_ref().map_or(0.0, |f| f.drop);
                depth = water::scour_depth(drop, s.flow, s.width, *radius);
            }
            Pool {
                node: p.node,
                kind: p.kind,
                level: p.level,
                area: p.area,
                depth,
                outline: p.outline.clone(),
                outlet: p.outlet.map(|o| o.to_array()),
                fall: p.fall,
            }
        })
        .collect()
}
