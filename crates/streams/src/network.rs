//! The hydraulic graph while it is being traced: nodes on the water surface, directed segments
//! downstream, pools with the grid cells they cover, and a spatial hash to find where a new
//! trajectory meets an older one (a confluence).

use std::collections::HashMap;

use glam::DVec3;

use crate::payload::{Fall, Motion, Outline, PoolKind, Role};

/// A segment being built.
#[derive(Debug, Clone)]
pub struct Edge {
    pub from: u32,
    pub to: u32,
    pub motion: Motion,
    /// Index of the controller curve it follows.
    pub curve: Option<usize>,
    pub fall: Option<Fall>,
}

/// A pool being built.
#[derive(Debug, Clone)]
pub struct PoolDraft {
    pub node: u32,
    pub kind: PoolKind,
    pub level: f64,
    pub area: f64,
    /// Depth of the water below the level before any digging (hollows), metres.
    pub depth: f64,
    pub outline: Outline,
    pub outlet: Option<DVec3>,
    /// The edge of the free fall landing in it.
    pub fall: Option<u32>,
}

/// The graph under construction.
#[derive(Debug, Default)]
pub struct Network {
    pub positions: Vec<DVec3>,
    pub roles: Vec<Role>,
    /// Water entering at each node from a spring or a curve, m³/s.
    pub source: Vec<f64>,
    pub edges: Vec<Edge>,
    /// Outgoing and incoming edges of each node.
    pub out: Vec<Vec<u32>>,
    pub into: Vec<Vec<u32>>,
    pub pools: Vec<PoolDraft>,
    /// Grid cells covered by each pool: a trajectory reaching one joins the pool.
    pub pool_cells: HashMap<usize, usize>,
    pub reports: Vec<String>,
    /// Nodes by bucket of `bucket` metres.
    hash: HashMap<(i64, i64), Vec<u32>>,
    bucket: f64,
}

impl Network {
    pub fn new(bucket: f64) -> Network {
        Network { bucket, ..Network::default() }
    }

    fn key(&self, p: DVec3) -> (i64, i64) {
        ((p.x / self.bucket).floor() as i64, (p.y / self.bucket).floor() as i64)
    }

    pub fn add_node(&mut self, p: DVec3, role: Role) -> u32 {
        let id = self.positions.len() as u32;
        self.positions.push(p);
        self.roles.push(role);
        self.source.push(0.0);
        self.out.push(Vec::new());
        self.into.push(Vec::new());
        let key = self.key(p);
        self.hash.entry(key).or_default().push(id);
        id
    }

    pub fn add_edge(
        &mut self,
        from: u32,
        to: u32,
        motion: Motion,
        curve: Option<usize>,
        fall: Option<Fall>,
    ) -> u32 {
        let id = self.edges.len() as u32;
        self.edges.push(Edge { from, to, motion, curve, fall });
        self.out[from as usize].push(id);
        self.into[to as usize].push(id);
        id
    }

    /// True when water leaving `a` can reach `b`.
    pub fn reaches(&self, a: u32, b: u32) -> bool {
        let mut seen = vec![false; self.positions.len()];
        let mut stack = vec![a];
        while let Some(n) = stack.pop() {
            if n == b {
                return true;
            }
            if std::mem::replace(&mut seen[n as usize], true) {
                continue;
            }
            stack.extend(self.out[n as usize].iter().map(|&e| self.edges[e as usize].to));
        }
        false
    }

    /// The node nearest to `p` horizontally within `radius` that water from `from` may flow
    /// into: at least `min_slope` per metre below it (Fig. 5), without making a loop (smallest
    /// index on a tie).
    pub fn joinable(&self, p: DVec3, radius: f64, from: u32, min_slope: f64) -> Option<u32> {
        let (i, j) = self.key(p);
        let reach = (radius / self.bucket).ceil() as i64;
        let source = self.positions[from as usize];
        let mut best: Option<(f64, u32)> = None;
        for di in -reach..=reach {
            for dj in -reach..=reach {
                for &n in self.hash.get(&(i + di, j + dj)).into_iter().flatten() {
                    let q = self.positions[n as usize];
                    let d = p.truncate().distance(q.truncate());
                    let lower = source.z - q.z >= min_slope * source.truncate().distance(q.truncate());
                    let better = best.is_none_or(|(bd, bn)| d < bd || (d == bd && n < bn));
                    if n != from && d <= radius && lower && better {
                        best = Some((d, n));
                    }
                }
            }
        }
        best.map(|(_, n)| n).filter(|&n| !self.reaches(n, from))
    }

    /// The pool covering grid cell `cell`, when water from `from` may flow into it.
    pub fn pool_at(&self, cell: usize, from: u32) -> Option<u32> {
        let pool = &self.pools[*self.pool_cells.get(&cell)?];
        (pool.node != from && !self.reaches(pool.node, from)).then_some(pool.node)
    }

    /// Forgets the nodes from index `nodes` on and the edges from index `edges` on: the tail
    /// of the trajectory being traced, which nothing older refers to.
    pub fn truncate(&mut self, nodes: usize, edges: usize) {
        for e in &self.edges[edges..] {
            let (from, to) = (e.from as usize, e.to as usize);
            if from < nodes {
                self.out[from].retain(|&k| (k as usize) < edges);
            }
            if to < nodes {
                self.into[to].retain(|&k| (k as usize) < edges);
            }
        }
        for n in nodes..self.positions.len() {
            let key = self.key(self.positions[n]);
            if let Some(bucket) = self.hash.get_mut(&key) {
                bucket.retain(|&k| (k as usize) < nodes);
            }
        }
        self.edges.truncate(edges);
        self.positions.truncate(nodes);
        self.roles.truncate(nodes);
        self.source.truncate(nodes);
        self.out.truncate(nodes);
        self.into.truncate(nodes);
    }
}
