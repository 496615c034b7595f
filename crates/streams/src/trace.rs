//! Trajectories adapted to the terrain (Emilien et al. 2015 §5.1, Fig. 5): from a source the
//! water steps downhill along the steepest descent, each point at least `min_slope` per metre
//! lower than the last (where the ground does not drop that much the stream cuts into it:
//! the riverbed carving of §6 digs that channel).
//!
//! Each step is subdivided where its midpoint lies off the terrain (§5.1, Fig. 7): the midpoint
//! moves onto the ground within the minimum slope to both ends, and the halves are refined again.
//!
//! Before each step the water's own parabola is compared with the ground: water moving at
//! speed δ = k·s (§5.2.2) along the slope it has follows z(s) = z − tan θ·s − g s²/(2 v_h²)
//! once it leaves the ground. Where the ground ahead lies below that parabola (a lip), the
//! ground drops faster than the water can follow and the water falls freely along the
//! parabola until it meets the ground; there it digs a plunge pool, whose level is the
//! lowest ground around it, and leaves at that lowest point.
//!
//! Where there is no way down (a hollow, a flat, or a valley floor where the descent turns
//! back) the hollow is filled to its spill point ([`crate::flood`]): a pool, or a lake when
//! larger than `lake_area` (reported); a hollow too shallow to hold water is crossed along
//! the flood's route. A trajectory ends at the footprint's edge (a well), or where it meets
//! an older trajectory or pool lower than itself (a confluence).
//!
//! No step climbs (Fig. 5): water that meets a pool or a hollow whose surface lies above it
//! has run under that surface, so the steps since it crossed the surface are dropped and it
//! enters there; water turning back under the surface of the hollow it has just left follows
//! the filled ground's way out instead ([`crate::flood`]).

use glam::{DVec2, DVec3};

use karst_hydro::G;
use karst_scene::params::StreamsParams;

use crate::flood::{self, Filled};
use crate::ground::{Grid, Ground};
use crate::network::{Network, PoolDraft};
use crate::payload::{Fall, Motion, Outline, PoolKind, Role};

/// Water shallower than this does not make a pool, metres.
const MIN_POOL_DEPTH: f64 = 0.1;
/// The ground must lie this far below the water's parabola for the water to leave it, metres.
const LIP_TOLERANCE: f64 = 0.05;
/// A stream cuts at most this many steps' worth of min-slope below the ground before the
/// rising ground counts as a hollow.
const MAX_CUT_STEPS: f64 = 1.0;

/// Ground steeper than this (rise over run) holds no pool: falling water meeting it runs on.
const STEEPEST_POOL: f64 = 1.0;

/// A step is subdivided where its midpoint lies farther than this off the terrain, metres
/// (§5.1), at most `REFINE_DEPTH` times (a step of 2 m into pieces of 25 cm).
const REFINE_TOLERANCE: f64 = 0.1;
const REFINE_DEPTH: u32 = 3;

/// How water moves when it leaves a point: horizontal direction and speed, vertical speed.
#[derive(Debug, Clone, Copy)]
pub struct Velocity {
    pub direction: DVec2,
    pub horizontal: f64,
    pub vertical: f64,
}

pub struct Tracer<'a> {
    ground: &'a Ground<'a>,
    grid: &'a Grid,
    params: &'a StreamsParams,
    net: &'a mut Network,
    /// The footprint filled to its spill points.
    filled: Filled,
    /// The nodes of the contact steps traced since the water last left a source, a pool or a
    /// fall, in order: where a trajectory that meets water above itself is corrected.
    trail: Vec<u32>,
}

/// What ended one step.
enum Next {
    Go(u32, Option<Velocity>),
    Stop,
}

impl<'a> Tracer<'a> {
    pub fn new(
        ground: &'a Ground<'a>,
        grid: &'a Grid,
        params: &'a StreamsParams,
        net: &'a mut Network,
    ) -> Self {
        Tracer { ground, grid, params, net, filled: flood::fill(grid), trail: Vec::new() }
    }

    /// Traces the water leaving node `start` (named `source` in reports) to a well or a
    /// confluence.
    pub fn trace(&mut self, start: u32, velocity: Option<Velocity>, source: &str) {
        self.run(Next::Go(start, velocity), source);
    }

    /// The water landing at the foot of the free fall `edge` (a fall controller): its plunge
    /// pool, then the trajectory on.
    pub fn land(&mut self, edge: u32, source: &str) {
        let e = &self.net.edges[edge as usize];
        let (lip, foot) = (self.net.positions[e.from as usize], self.net.positions[e.to as usize]);
        let (radius, level, outlet) = self.plunge_site(foot.truncate(), lip.z - foot.z);
        let next = self.plunge(e.to, edge, radius, level.min(foot.z), outlet);
        self.run(next, source);
    }

    /// The water spilling from pool node `pool` at `outlet`, then the trajectory on.
    pub fn spill(&mut self, pool: u32, outlet: DVec2, level: f64, source: &str) {
        let next = self.leave_pool(pool, outlet, level);
        self.run(next, source);
    }

    fn run(&mut self, first: Next, source: &str) {
        let Next::Go(mut at, mut velocity) = first else { return };
        self.trail = vec![at];
        let mut travelled = 0.0;
        loop {
            if travelled > self.params.max_length {
                self.net.roles[at as usize] = Role::Well;
                self.net.reports.push(format!(
                    "{source}: the trajectory stops after streams.max_length = {} m at {}",
                    self.params.max_length,
                    show(self.net.positions[at as usize])
                ));
                return;
            }
            let before = self.net.positions[at as usize];
            match self.step(at, velocity, source) {
                Next::Go(next, v) => {
                    travelled += before.truncate().distance(self.net.positions[next as usize].truncate());
                    (at, velocity) = (next, v);
                }
                Next::Stop => return,
            }
        }
    }

    fn step(&mut self, at: u32, velocity: Option<Velocity>, source: &str) -> Next {
        let p = self.net.positions[at as usize];
        let p2 = p.truncate();
        let gradient = self.ground.gradient(p2);
        let steepness = gradient.length();
        if steepness.is_nan() || steepness < 0.5 * self.params.min_slope {
            return self.hollow(at, source);
        }
        let direction = -gradient / steepness;
        if velocity.is_some_and(|v| v.direction.dot(direction) < -0.3) {
            return self.hollow(at, source);
        }
        let mut q = p2 + direction * self.params.step;
        let leaving = !self.ground.inside(q);
        if leaving {
            q = self.ground.edge_point(p2, q);
        }
        let run = q.distance(p2);
        if run <= 1e-9 {
            self.net.roles[at as usize] = Role::Well;
            return Next::Stop;
        }
        let ground = self.ground.height(q);
        let v = velocity.unwrap_or_else(|| self.running(steepness.atan(), direction));
        let flight = v.vertical / v.horizontal * run - G * run * run / (2.0 * v.horizontal * v.horizontal);
        let v = Velocity { direction, ..v };
        // The water leaves the ground where the ground drops below its parabola, and flies
        // farther than a step before it meets the ground again.
        if ground < p.z + flight - LIP_TOLERANCE
            && self.flight(p, v, (self.params.step / 8.0).min(0.25)).0 > self.params.step
        {
            return self.fall(at, v);
        }
        let z = ground.min(p.z - self.params.min_slope * run);
        if ground - z > MAX_CUT_STEPS * self.params.step && !leaving {
            return self.hollow(at, source);
        }
        let point = q.extend(z);
        if self.turns_back(point) {
            // The water would run back under the surface of the hollow it left: it follows
            // the filled ground's way out instead.
            let route = self.filled.route(self.grid.cell_of(p2));
            return self.cross(at, &route);
        }
        if let Some((from, joined)) = self.join(at, point) {
            self.net.add_edge(from, joined, Motion::Contact, None, None);
            return Next::Stop;
        }
        let next = self.contact_step(at, point, if leaving { Role::Well } else { Role::Branch });
        if leaving {
            return Next::Stop;
        }
        let slope = ((p.z - z) / run).atan();
        Next::Go(next, Some(self.running(slope, direction)))
    }

    /// The contact step from node `at` to a new node at `point` (role `role`), subdivided where
    /// it leaves the terrain; returns the new node.
    fn contact_step(&mut self, at: u32, point: DVec3, role: Role) -> u32 {
        let mut inner = Vec::new();
        self.refine(self.net.positions[at as usize], point, REFINE_DEPTH, &mut inner);
        let roles = std::iter::repeat_n(Role::Branch, inner.len()).chain([role]);
        let mut last = at;
        for (p, role) in inner.into_iter().chain([point]).zip(roles) {
            let node = self.net.add_node(p, role);
            self.net.add_edge(last, node, Motion::Contact, None, None);
            self.trail.push(node);
            last = node;
        }
        last
    }

    /// The points between `a` and `b`, in order, that keep the water on the terrain (§5.1's
    /// subdivision, Fig. 7, along the step): where the piece's midpoint lies more than
    /// `REFINE_TOLERANCE` off the ground (over a convex lip it cuts the rock, over a notch it
    /// bridges it), the midpoint moves onto the ground, as deep under it as the piece's ends
    /// are on average, within the minimum slope to both ends; both halves are refined again.
    fn refine(&self, a: DVec3, b: DVec3, depth: u32, out: &mut Vec<DVec3>) {
        let m = 0.5 * (a.truncate() + b.truncate());
        let half = a.truncate().distance(m);
        let cut = |p: DVec3| self.ground.height(p.truncate()) - p.z;
        let slope = self.params.min_slope;
        let onto = self.ground.height(m) - 0.5 * (cut(a) + cut(b));
        let z = onto.max(b.z + slope * half).min(a.z - slope * half);
        if depth == 0 || (z - 0.5 * (a.z + b.z)).abs() <= REFINE_TOLERANCE {
            return;
        }
        let mid = m.extend(z);
        self.refine(a, mid, depth - 1, out);
        out.push(mid);
        self.refine(mid, b, depth - 1, out);
    }

    /// Water running down `slope` radians along `direction` at δ = k·s.
    fn running(&self, slope: f64, direction: DVec2) -> Velocity {
        let speed = self.params.speed_factor * slope.max(self.params.min_slope.atan());
        Velocity { direction, horizontal: speed * slope.cos(), vertical: -speed * slope.sin() }
    }

    /// An older pool or node that a stream at `point` coming from `at` flows into, and the node
    /// the step into it starts from (`at`, or an earlier node of the trail when the pool's
    /// surface lies above `at`).
    fn join(&mut self, at: u32, point: DVec3) -> Option<(u32, u32)> {
        self.pool_entry(self.grid.cell_of(point.truncate()), at).or_else(|| {
            self.net.joinable(point, 0.6 * self.params.step, at, self.params.min_slope).map(|n| (at, n))
        })
    }

    /// The older pool covering `cell` that the water at `at` flows into, and the node of the
    /// trail the step into it starts from.
    fn pool_entry(&mut self, cell: usize, at: u32) -> Option<(u32, u32)> {
        let pool = self.net.pool_at(cell, at)?;
        self.entry(self.net.positions[pool as usize]).map(|from| (from, pool))
    }

    /// Where the water of the trail meets water lying at `surface`: the latest node of the
    /// trail at least `min_slope` per metre above it (Fig. 5: a step never climbs). The trail
    /// after that node ran under that water's surface: it is forgotten, the water enters there.
    fn entry(&mut self, surface: DVec3) -> Option<u32> {
        let k = self.trail.iter().rposition(|&n| self.drops(n, surface))?;
        self.forget_after(k);
        Some(self.trail[k])
    }

    /// Forgets the trail after its `k`-th node, with the steps that led there.
    fn forget_after(&mut self, k: usize) {
        if let Some(&first) = self.trail.get(k + 1) {
            // The trail's nodes and their edges are the newest of the network.
            let edge = self.net.into[first as usize][0];
            debug_assert!(self.trail[k + 1..].iter().zip(first..).all(|(&n, m)| n == m));
            self.net.truncate(first as usize, edge as usize);
            self.trail.truncate(k + 1);
        }
    }

    /// True when `point` lies under the filled level of a hollow that the trail's water cannot
    /// fill: no node of the trail lies above that level, and the trail does not start at a
    /// spring (the water is turning back into the hollow it has just left).
    fn turns_back(&self, point: DVec3) -> bool {
        let cell = self.grid.cell_of(point.truncate());
        let level = self.filled.level[cell];
        let surface = point.truncate().extend(level);
        level > self.grid.heights[cell]
            && point.z < level
            && !self.trail.iter().any(|&n| self.drops(n, surface))
            && !self.is_spring(self.trail[0])
    }

    /// True when a contact step from node `n` to `target` drops `min_slope` per metre.
    fn drops(&self, n: u32, target: DVec3) -> bool {
        let p = self.net.positions[n as usize];
        p.z - target.z >= self.params.min_slope * p.truncate().distance(target.truncate())
    }

    /// True for a spring's node that no water has reached yet.
    fn is_spring(&self, n: u32) -> bool {
        self.net.roles[n as usize] == Role::Source && self.net.into[n as usize].is_empty()
    }

    /// The node where the water of the trail enters a new pool whose surface is `surface`: a
    /// node on that surface reached from the trail, or the trail's source itself when even the
    /// spring's mouth lies under that surface (the spring feeds the pool from below).
    fn pool_node(&mut self, surface: DVec3) -> Option<u32> {
        if let Some(from) = self.entry(surface) {
            let node = self.net.add_node(surface, Role::Pool);
            self.net.add_edge(from, node, Motion::Contact, None, None);
            return Some(node);
        }
        let spring = self.trail[0];
        if !self.is_spring(spring) {
            return None;
        }
        self.forget_after(0);
        self.net.positions[spring as usize].z = surface.z;
        self.net.roles[spring as usize] = Role::Pool;
        Some(spring)
    }

    /// How far the water leaving `lip` with velocity `v` flies horizontally before it meets
    /// the ground, and whether it leaves the footprint first.
    fn flight(&self, lip: DVec3, v: Velocity, ds: f64) -> (f64, bool) {
        let height =
            |s: f64| lip.z + v.vertical / v.horizontal * s - G * s * s / (2.0 * v.horizontal * v.horizontal);
        let mut s = 0.0;
        loop {
            s += ds;
            let xy = lip.truncate() + v.direction * s;
            if !self.ground.inside(xy) {
                return (self.ground.edge_point(lip.truncate(), xy).distance(lip.truncate()), true);
            }
            if height(s) <= self.ground.height(xy) - LIP_TOLERANCE {
                return (s, false);
            }
        }
    }

    /// The free fall from `at` leaving with velocity `v`, its plunge pool and what follows.
    fn fall(&mut self, at: u32, v: Velocity) -> Next {
        let lip = self.net.positions[at as usize];
        let ds = (self.params.step / 8.0).min(0.25);
        let height =
            |s: f64| lip.z + v.vertical / v.horizontal * s - G * s * s / (2.0 * v.horizontal * v.horizontal);
        let (mut s, edge) = self.flight(lip, v, ds);
        let touch = lip.truncate() + v.direction * s;
        if !edge {
            let below_lip = |pool: &u32| self.net.positions[*pool as usize].z < lip.z;
            if let Some(pool) = self.net.pool_at(self.grid.cell_of(touch), at).filter(below_lip) {
                // It falls into a pool already there.
                let level = self.net.positions[pool as usize].z;
                while height(s) > level && s < 1e6 {
                    s += ds;
                }
                let fall = parabola(lip, v, s, height(s));
                self.net.add_edge(at, pool, Motion::FreeFall, None, Some(fall));
                return Next::Stop;
            }
            if self.ground.gradient(touch).length() > STEEPEST_POOL {
                // It meets a wall too steep to hold a pool: it runs on down the wall.
                let foot = self.net.add_node(touch.extend(height(s)), Role::Branch);
                self.net.add_edge(at, foot, Motion::FreeFall, None, Some(parabola(lip, v, s, height(s))));
                self.trail = vec![foot];
                return Next::Go(foot, None);
            }
        }
        let (radius, level, outlet) = if edge {
            (0.0, height(s), touch)
        } else {
            self.plunge_site(touch, lip.z - self.ground.height(touch))
        };
        // The water falls on to the pool's surface.
        while !edge && height(s) > level && s < 1e6 {
            s += ds;
        }
        let fall = parabola(lip, v, s, height(s).max(level));
        let impact = DVec3::from_array(fall.impact);
        let foot = self.net.add_node(impact, if edge { Role::Well } else { Role::Pool });
        let edge_id = self.net.add_edge(at, foot, Motion::FreeFall, None, Some(fall));
        if edge {
            return Next::Stop;
        }
        self.plunge(foot, edge_id, radius, level, outlet)
    }

    /// The plunge pool at node `foot` where the fall `edge` lands, and the water leaving it.
    fn plunge(&mut self, foot: u32, edge: u32, radius: f64, level: f64, outlet: DVec2) -> Next {
        let centre = self.net.positions[foot as usize].truncate();
        self.net.pools.push(PoolDraft {
            node: foot,
            kind: PoolKind::Plunge,
            level,
            area: std::f64::consts::PI * radius * radius,
            depth: 0.0,
            outline: Outline::Disc { centre: centre.to_array(), radius },
            outlet: Some(outlet.extend(level)),
            fall: Some(edge),
        });
        self.cover_disc(centre, radius, self.net.pools.len() - 1);
        self.leave_pool(foot, outlet, level)
    }

    /// Radius, level and outlet of the plunge pool where a fall of `drop` metres meets the
    /// ground at `touch`: the level is the lowest ground on its rim, where the water leaves.
    fn plunge_site(&self, touch: DVec2, drop: f64) -> (f64, f64, DVec2) {
        let radius = (1.0 + 0.15 * drop).clamp(1.5, 12.0);
        let mut best = (self.ground.height(touch), touch);
        for k in 0..32 {
            let angle = k as f64 * std::f64::consts::TAU / 32.0;
            let dir = DVec2::from_angle(angle);
            for r in [radius, radius + 0.5 * self.params.step] {
                let q = touch + dir * r;
                if !self.ground.inside(q) {
                    continue;
                }
                let h = self.ground.height(q);
                if h < best.0 {
                    best = (h, touch + dir * radius);
                }
            }
        }
        (radius, best.0, best.1)
    }

    /// The edge leaving pool node `pool` at `outlet` (level `level`) and the trajectory on.
    fn leave_pool(&mut self, pool: u32, outlet: DVec2, level: f64) -> Next {
        let from = self.net.positions[pool as usize];
        let run = from.truncate().distance(outlet).max(1e-3);
        let z = self.ground.height(outlet).min(level - self.params.min_slope * run);
        let point = outlet.extend(z);
        let next = self.net.add_node(point, Role::Branch);
        self.net.add_edge(pool, next, Motion::Pool, None, None);
        self.trail = vec![next];
        Next::Go(next, None)
    }

    fn cover_disc(&mut self, centre: DVec2, radius: f64, pool: usize) {
        for c in 0..self.grid.heights.len() {
            if self.grid.centre(c).distance(centre) <= radius {
                self.net.pool_cells.entry(c).or_insert(pool);
            }
        }
    }

    /// No way down from `at`: fill the hollow, or cross it when too shallow.
    fn hollow(&mut self, at: u32, source: &str) -> Next {
        let p = self.net.positions[at as usize];
        let cell = self.grid.cell_of(p.truncate());
        if let Some((from, pool)) = self.pool_entry(cell, at) {
            self.net.add_edge(from, pool, Motion::Contact, None, None);
            return Next::Stop;
        }
        let hollow = self.filled.hollow(self.grid, cell);
        let depth = hollow.flooded.iter().map(|&c| hollow.level - self.grid.heights[c]).fold(0.0, f64::max);
        let surface = p.truncate().extend(hollow.level);
        let node = if depth < MIN_POOL_DEPTH { None } else { self.pool_node(surface) };
        let Some(node) = node else {
            // Too shallow to hold water, or the trail started under the pool's surface (the
            // water of an upstream pool or fall running back into its own hollow): the stream
            // crosses the hollow along the flood's route, cutting its bed.
            return self.cross(at, &hollow.route);
        };
        let area = hollow.flooded.len() as f64 * self.grid.area();
        let lake = area > self.params.lake_area;
        let index = self.net.pools.len();
        if lake {
            self.net.reports.push(format!(
                "{source}: the water cannot leave the hollow at {} without filling a lake of {area:.0} m² \
                 at z = {:.2} m (pools[{index}])",
                show(p),
                hollow.level
            ));
        }
        self.net.pools.push(PoolDraft {
            node,
            kind: if lake { PoolKind::Lake } else { PoolKind::Basin },
            level: hollow.level,
            area,
            depth,
            outline: Outline::Cells { rectangles: rectangles(self.grid, &hollow.flooded) },
            outlet: Some(self.grid.centre(hollow.outlet).extend(hollow.level)),
            fall: None,
        });
        for &c in &hollow.flooded {
            self.net.pool_cells.entry(c).or_insert(index);
        }
        self.leave_pool(node, self.grid.centre(hollow.outlet), hollow.level)
    }

    /// Crosses a flat or shallow hollow along the flood's `route`, keeping the minimum slope.
    fn cross(&mut self, at: u32, route: &[usize]) -> Next {
        let mut last = at;
        for &c in route.iter().skip(1) {
            let from = self.net.positions[last as usize];
            let q = self.grid.centre(c);
            let run = from.truncate().distance(q);
            let point = q.extend(self.ground.height(q).min(from.z - self.params.min_slope * run));
            if let Some((from, joined)) = self.join(last, point) {
                self.net.add_edge(from, joined, Motion::Contact, None, None);
                return Next::Stop;
            }
            let next = self.net.add_node(point, Role::Branch);
            self.net.add_edge(last, next, Motion::Contact, None, None);
            self.trail.push(next);
            last = next;
        }
        if last == at {
            // Nowhere to go: the water stays (the route is the hollow itself).
            self.net.roles[at as usize] = Role::Well;
            return Next::Stop;
        }
        Next::Go(last, None)
    }
}

/// The fall from `lip` with velocity `v` over a horizontal distance `throw`, down to `z`.
fn parabola(lip: DVec3, v: Velocity, throw: f64, z: f64) -> Fall {
    let impact = (lip.truncate() + v.direction * throw).extend(z);
    Fall {
        lip: lip.to_array(),
        direction: v.direction.to_array(),
        speed: v.horizontal,
        vertical: v.vertical,
        drop: lip.z - z,
        throw,
        impact: impact.to_array(),
    }
}

/// The flooded cells merged into one rectangle per run along each row.
fn rectangles(grid: &Grid, cells: &[usize]) -> Vec<[f64; 4]> {
    let mut sorted = cells.to_vec();
    sorted.sort_unstable();
    let mut out: Vec<[f64; 4]> = Vec::new();
    let mut previous: Option<usize> = None;
    for c in sorted {
        let lo = grid.centre(c) - DVec2::splat(0.5 * grid.cell);
        let extends = previous.is_some_and(|p| p + 1 == c && c % grid.nx != 0);
        match out.last_mut() {
            Some(r) if extends => r[2] = lo.x + grid.cell,
            _ => out.push([lo.x, lo.y, lo.x + grid.cell, lo.y + grid.cell]),
        }
        previous = Some(c);
    }
    out
}

fn show(p: DVec3) -> String {
    format!("[{:.1}, {:.1}, {:.1}]", p.x, p.y, p.z)
}
