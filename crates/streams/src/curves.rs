//! The user's controller network (Emilien et al. 2015 §4.1): contact curves (Cardinal splines
//! through their control points), free falls (a parabola from the lip to the foot) and pools
//! (a flat closed spline at the mean elevation of its points).
//!
//! A curve's first point within `streams.snap` of a spring's mouth takes that spring's water
//! (the spring is no longer traced on its own); near a control point of another curve it
//! branches off there (the water is split by w = 1 + u·v); inside or near a pool it is one of
//! the pool's outlets; elsewhere it is a source of its own `flow`. Its last point likewise
//! joins a curve or a pool, or the water runs on from it over the terrain (a fall's foot gets
//! a plunge pool).
//!
//! Minimum slope (Fig. 5): in dependency order from the sources, every control point must lie
//! at least `min_slope` per metre below the previous one (a curve's first point below the
//! point it leaves, a pool's level below every curve ending in it); points that do not are
//! lowered to the limit, each reported. Between control points the spline's own overshoot is
//! flattened the same way without report.

use glam::{DVec2, DVec3};

use karst_scene::params::{Curve, CurveKind, StreamsParams};

use crate::ground::Ground;
use crate::heading;
use crate::network::{Network, PoolDraft};
use crate::payload::{Fall, Motion, Outline, PoolKind, Role};

/// Where the water goes on after the controller network.
#[derive(Debug, Clone, PartialEq)]
pub enum End {
    /// Runs on over the terrain from the node.
    Trace { node: u32, name: String },
    /// Lands at the foot of the free fall `edge` (a plunge pool), then runs on.
    Land { edge: u32, name: String },
    /// Spills from pool node `pool` at `outlet` (level `level`).
    Spill { pool: u32, outlet: DVec2, level: f64, name: String },
}

/// What laying the curves did.
#[derive(Debug, Default)]
pub struct Laid {
    /// Spring nodes whose water a curve takes.
    pub captured: Vec<u32>,
    pub ends: Vec<End>,
}

/// What a curve's end touches.
#[derive(Debug, Clone, Copy, PartialEq)]
enum Attach {
    Spring(u32),
    Point { curve: usize, point: usize },
    Pool(usize),
    Nothing,
}

/// Lays the scene's curves into `net`; `springs` are the spring source nodes.
pub fn lay(
    params: &StreamsParams,
    ground: &Ground,
    net: &mut Network,
    springs: &[(u32, DVec2, String)],
) -> Laid {
    let curves = &params.curves;
    let mut points: Vec<Vec<DVec3>> =
        curves.iter().map(|c| c.points.iter().map(|p| DVec3::from_array(*p)).collect()).collect();
    let starts: Vec<Attach> =
        (0..curves.len()).map(|i| attach(curves, &points, i, 0, net, springs, params.snap)).collect();
    let ends: Vec<Attach> = (0..curves.len())
        .map(|i| match curves[i].kind {
            CurveKind::Pool => Attach::Nothing,
            _ => attach(curves, &points, i, curves[i].points.len() - 1, net, &[], params.snap),
        })
        .collect();
    let order = dependency_order(&starts, &ends, &mut net.reports, curves);
    let mut laid = Laid::default();
    let mut nodes: Vec<Vec<u32>> = vec![Vec::new(); curves.len()];
    let mut pool_of: Vec<Option<usize>> = vec![None; curves.len()];
    for &i in &order {
        let curve = &curves[i];
        let upstream = match starts[i] {
            Attach::Spring(node) => Some(net.positions[node as usize].z),
            Attach::Point { curve: c, point } => Some(points[c][point].z),
            Attach::Pool(c) => Some(level(&points[c])),
            Attach::Nothing => None,
        };
        if curve.kind == CurveKind::Pool {
            let incoming: Vec<f64> = (0..curves.len())
                .filter(|&j| ends[j] == Attach::Pool(i))
                .map(|j| points[j].last().map_or(f64::INFINITY, |p| p.z))
                .collect();
            lower_pool(&mut points[i], &incoming, i, curve, &mut net.reports);
        } else {
            lower(&mut points[i], upstream, params.min_slope, i, curve, &mut net.reports);
        }
        let first = match starts[i] {
            Attach::Spring(node) => {
                laid.captured.push(node);
                Some(node)
            }
            Attach::Point { curve: c, point } => nodes[c].get(point).copied(),
            Attach::Pool(c) => pool_of[c].map(|p| net.pools[p].node),
            Attach::Nothing => None,
        };
        match curve.kind {
            CurveKind::Contact => {
                nodes[i] = contact(net, &points[i], curve, i, first, params.step, params.min_slope);
            }
            CurveKind::FreeFall => {
                let start = first.unwrap_or_else(|| source(net, points[i][0], curve));
                let foot = net.add_node(points[i][1], Role::Branch);
                let edge = net.add_edge(
                    start,
                    foot,
                    Motion::FreeFall,
                    Some(i),
                    Some(parabola(points[i][0], points[i][1])),
                );
                nodes[i] = vec![start, foot];
                if ends[i] == Attach::Nothing {
                    net.roles[foot as usize] = Role::Pool;
                    laid.ends.push(End::Land { edge, name: curve.name.clone() });
                }
            }
            CurveKind::Pool => {
                let (node, pool) = pool(net, ground, &points[i], curve, params.step);
                nodes[i] = vec![node];
                pool_of[i] = Some(pool);
            }
        }
    }
    // Join the ends, and let the water run on from the open ones.
    for &i in &order {
        let Some(&last) = nodes[i].last() else { continue };
        match (curves[i].kind, ends[i]) {
            (CurveKind::Pool, _) if !starts.contains(&Attach::Pool(i)) => {
                if let Some(p) = pool_of[i].map(|p| &net.pools[p]) {
                    let outlet = p.outlet.map_or(DVec2::ZERO, |o| o.truncate());
                    laid.ends.push(End::Spill {
                        pool: p.node,
                        outlet,
                        level: p.level,
                        name: curves[i].name.clone(),
                    });
                }
            }
            (_, Attach::Point { curve: c, point }) => {
                let target = nodes[c].get(point).copied().unwrap_or(last);
                if target != last && !net.reaches(target, last) {
                    net.add_edge(last, target, Motion::Contact, Some(i), None);
                }
            }
            (_, Attach::Pool(c)) => {
                if let Some(target) = pool_of[c].map(|p| net.pools[p].node)
                    && !net.reaches(target, last)
                {
                    net.add_edge(last, target, Motion::Contact, Some(i), None);
                }
            }
            (CurveKind::Contact, _) if !continued(&starts, i, curves[i].points.len() - 1) => {
                laid.ends.push(End::Trace { node: last, name: curves[i].name.clone() });
            }
            _ => {}
        }
    }
    laid
}

/// True when some curve starts at control point `point` of curve `curve`.
fn continued(starts: &[Attach], curve: usize, point: usize) -> bool {
    starts.contains(&Attach::Point { curve, point })
}

/// What point `k` of curve `i` touches (springs only for first points).
fn attach(
    curves: &[Curve],
    points: &[Vec<DVec3>],
    i: usize,
    k: usize,
    net: &Network,
    springs: &[(u32, DVec2, String)],
    snap: f64,
) -> Attach {
    let p = points[i][k];
    if let Some((node, ..)) = springs.iter().find(|(n, ..)| net.positions[*n as usize].distance(p) <= snap) {
        return Attach::Spring(*node);
    }
    for (j, other) in curves.iter().enumerate().filter(|(j, _)| *j != i) {
        if other.kind == CurveKind::Pool {
            let outline: Vec<DVec2> = points[j].iter().map(|q| q.truncate()).collect();
            if polygon_distance(&outline, p.truncate()) <= snap {
                return Attach::Pool(j);
            }
            continue;
        }
        let nearest = (0..points[j].len())
            .map(|m| (points[j][m].distance(p), m))
            .filter(|(d, _)| *d <= snap)
            .min_by(|a, b| a.0.total_cmp(&b.0));
        if let Some((_, point)) = nearest {
            return Attach::Point { curve: j, point };
        }
    }
    Attach::Nothing
}

/// Curves so that each comes after the curves its water comes from; a connection that would
/// close a loop is dropped and reported.
fn dependency_order(
    starts: &[Attach],
    ends: &[Attach],
    reports: &mut Vec<String>,
    curves: &[Curve],
) -> Vec<usize> {
    let n = starts.len();
    let upstream = |i: usize| -> Vec<usize> {
        let mut up: Vec<usize> = match starts[i] {
            Attach::Point { curve, .. } | Attach::Pool(curve) => vec![curve],
            _ => vec![],
        };
        up.extend((0..n).filter(|&j| ends[j] == Attach::Pool(i)));
        up
    };
    let mut state = vec![0u8; n];
    let mut order = Vec::new();
    fn visit(
        i: usize,
        up: &dyn Fn(usize) -> Vec<usize>,
        state: &mut [u8],
        order: &mut Vec<usize>,
        loops: &mut Vec<usize>,
    ) {
        if state[i] == 2 {
            return;
        }
        if state[i] == 1 {
            loops.push(i);
            return;
        }
        state[i] = 1;
        for j in up(i) {
            visit(j, up, state, order, loops);
        }
        state[i] = 2;
        order.push(i);
    }
    let mut loops = Vec::new();
    for i in 0..n {
        visit(i, &upstream, &mut state, &mut order, &mut loops);
    }
    for i in loops {
        reports.push(format!(
            "streams.curves[{i}] (\"{}\"): its connections make a loop; the water cannot flow round it",
            curves[i].name
        ));
    }
    order
}

/// Lowers the control points that do not fall by `min_slope` per metre (Fig. 5), reporting each.
fn lower(
    points: &mut [DVec3],
    upstream: Option<f64>,
    min_slope: f64,
    i: usize,
    curve: &Curve,
    reports: &mut Vec<String>,
) {
    let mut limit = upstream;
    for k in 0..points.len() {
        if k > 0 {
            let run = points[k].truncate().distance(points[k - 1].truncate());
            limit = Some(points[k - 1].z - min_slope * run.max(1e-3));
        }
        if let Some(top) = limit.filter(|&top| points[k].z > top) {
            reports.push(format!(
                "streams.curves[{i}] (\"{}\"): points[{k}] lowered from {:.2} to {:.2} m: water must go down by at \
                 least streams.min_slope = {min_slope} per metre (§4.1)",
                curve.name, points[k].z, top
            ));
            points[k].z = top;
        }
    }
}

/// A pool's level (the mean of its points), lowered below every curve ending in it.
fn lower_pool(points: &mut [DVec3], incoming: &[f64], i: usize, curve: &Curve, reports: &mut Vec<String>) {
    let mean = level(points);
    let top = incoming.iter().copied().fold(mean, f64::min);
    if top < mean {
        reports.push(format!(
            "streams.curves[{i}] (\"{}\"): pool lowered from {mean:.2} to {top:.2} m, below the curves flowing into it (§4.1)",
            curve.name
        ));
    }
    for p in points {
        p.z = top;
    }
}

fn level(points: &[DVec3]) -> f64 {
    points.iter().map(|p| p.z).sum::<f64>() / points.len().max(1) as f64
}

fn source(net: &mut Network, p: DVec3, curve: &Curve) -> u32 {
    let node = net.add_node(p, Role::Source);
    net.source[node as usize] = curve.flow.unwrap_or(0.0);
    node
}

/// Lays a contact curve: nodes along its spline about `step` apart, the control points among
/// them; returns the node of each control point.
fn contact(
    net: &mut Network,
    points: &[DVec3],
    curve: &Curve,
    i: usize,
    first: Option<u32>,
    step: f64,
    min_slope: f64,
) -> Vec<u32> {
    let mut at = first.unwrap_or_else(|| source(net, points[0], curve));
    let mut controls = vec![at];
    let mut z = net.positions[at as usize].z.min(points[0].z);
    for k in 0..points.len() - 1 {
        let samples = cardinal(points, k, curve.tension, false, step);
        for (m, p) in samples.iter().enumerate().skip(1) {
            let previous = net.positions[at as usize];
            z = p.z.min(z - min_slope * p.truncate().distance(previous.truncate()));
            let node = net.add_node(p.truncate().extend(z), Role::Branch);
            net.add_edge(at, node, Motion::Contact, Some(i), None);
            at = node;
            if m + 1 == samples.len() {
                controls.push(node);
            }
        }
    }
    controls
}

/// Samples span k → k + 1 of the Cardinal spline through `points` (tension c: tangents
/// (1 − c)(P_{k+1} − P_{k−1})/2), about `step` apart horizontally, both ends included.
pub fn cardinal(points: &[DVec3], k: usize, tension: f64, closed: bool, step: f64) -> Vec<DVec3> {
    let n = points.len();
    let at = |i: i64| -> DVec3 {
        if closed {
            points[i.rem_euclid(n as i64) as usize]
        } else {
            points[i.clamp(0, n as i64 - 1) as usize]
        }
    };
    let k = k as i64;
    let (p0, p1) = (at(k), at(k + 1));
    let m0 = (at(k + 1) - at(k - 1)) * (1.0 - tension) * 0.5;
    let m1 = (at(k + 2) - at(k)) * (1.0 - tension) * 0.5;
    let count = ((p1 - p0).truncate().length() / step).ceil().max(1.0) as usize;
    (0..=count)
        .map(|j| {
            let t = j as f64 / count as f64;
            let (t2, t3) = (t * t, t * t * t);
            p0 * (2.0 * t3 - 3.0 * t2 + 1.0)
                + m0 * (t3 - 2.0 * t2 + t)
                + p1 * (-2.0 * t3 + 3.0 * t2)
                + m1 * (t3 - t2)
        })
        .collect()
}

/// The parabola of a free fall from `lip` to `foot`, leaving the lip horizontally.
fn parabola(lip: DVec3, foot: DVec3) -> Fall {
    let drop = (lip.z - foot.z).max(1e-6);
    let throw = lip.truncate().distance(foot.truncate());
    Fall {
        lip: lip.to_array(),
        direction: heading(lip, foot).to_array(),
        speed: (throw * (karst_hydro::G / (2.0 * drop)).sqrt()).max(1e-6),
        vertical: 0.0,
        drop,
        throw,
        impact: foot.to_array(),
    }
}

/// Lays a pool controller: its node at the outline's centroid and level, its outline, its
/// depth one tenth of its equivalent diameter (at least half a metre); the water leaves at the
/// lowest ground along the outline unless curves leave it.
fn pool(net: &mut Network, ground: &Ground, points: &[DVec3], curve: &Curve, step: f64) -> (u32, usize) {
    let outline: Vec<DVec2> = (0..points.len())
        .flat_map(|k| {
            let span = cardinal(points, k, curve.tension, true, step);
            span.into_iter().skip(1).map(|p| p.truncate()).collect::<Vec<_>>()
        })
        .collect();
    let level = points[0].z;
    let area = polygon_area(&outline).abs();
    let centre = outline.iter().copied().sum::<DVec2>() / outline.len() as f64;
    let outlet = outline
        .iter()
        .copied()
        .min_by(|a, b| ground.height(*a).total_cmp(&ground.height(*b)))
        .unwrap_or(centre);
    let node = net.add_node(centre.extend(level), Role::Pool);
    if let Some(f) = curve.flow {
        net.source[node as usize] = f;
    }
    net.pools.push(PoolDraft {
        node,
        kind: PoolKind::Curve,
        level,
        area,
        depth: (0.1 * (4.0 * area / std::f64::consts::PI).sqrt()).max(0.5),
        outline: Outline::Polygon { points: outline.iter().map(|p| p.to_array()).collect() },
        outlet: Some(outlet.extend(level)),
        fall: None,
    });
    (node, net.pools.len() - 1)
}

/// Signed area (counter-clockwise positive).
pub fn polygon_area(points: &[DVec2]) -> f64 {
    let n = points.len();
    (0..n).map(|k| points[k].perp_dot(points[(k + 1) % n])).sum::<f64>() * 0.5
}

/// Distance from `p` to the polygon's region (0 inside).
pub fn polygon_distance(points: &[DVec2], p: DVec2) -> f64 {
    let n = points.len();
    let mut inside = false;
    let mut best = f64::INFINITY;
    for k in 0..n {
        let (a, b) = (points[k], points[(k + 1) % n]);
        if (a.y > p.y) != (b.y > p.y) && p.x < a.x + (p.y - a.y) / (b.y - a.y) * (b.x - a.x) {
            inside = !inside;
        }
        let ab = b - a;
        let t = if ab.length_squared() > 0.0 {
            ((p - a).dot(ab) / ab.length_squared()).clamp(0.0, 1.0)
        } else {
            0.0
        };
        best = best.min(p.distance(a + ab * t));
    }
    if inside { 0.0 } else { best }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_cardinal_spline_passes_through_its_points() {
        let pts = [DVec3::new(0.0, 0.0, 10.0), DVec3::new(10.0, 5.0, 8.0), DVec3::new(20.0, 0.0, 5.0)];
        for k in 0..2 {
            let s = cardinal(&pts, k, 0.5, false, 1.0);
            assert_eq!(s[0], pts[k]);
            assert!(s.last().unwrap().distance(pts[k + 1]) < 1e-12);
        }
        let straight = cardinal(&pts, 0, 1.0, false, 1.0);
        assert!(straight.iter().all(|p| (p.y - p.x / 2.0).abs() < 1e-9), "tension 1: straight lines");
    }

    #[test]
    fn polygons() {
        let square = [DVec2::ZERO, DVec2::new(2.0, 0.0), DVec2::new(2.0, 2.0), DVec2::new(0.0, 2.0)];
        assert_eq!(polygon_area(&square), 4.0);
        assert_eq!(polygon_distance(&square, DVec2::new(1.0, 1.0)), 0.0);
        assert_eq!(polygon_distance(&square, DVec2::new(5.0, 1.0)), 3.0);
    }
}
