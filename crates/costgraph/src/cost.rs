//! The cost of an edge: its length times the mean, along the edge, of a cost per metre.
//!
//! Two models, chosen by `costgraph.model` (docs/costgraph.md has the formulas and why):
//!
//! - **karstnsim2024** (Gouy et al. 2024 §1.3, eq. 1): per metre
//!   ε + α_I·C_I + α_F·C_F + α_WT·C_WT + α_P·C_P, with C_I = s(d_I) (Wyvill falloff of the
//!   distance to the nearest horizon or fault), C_F = 0 when the edge lies within the tolerance
//!   of a fracture family's plane and 1 otherwise, C_WT = 1 − arccos(e)/π above the water table
//!   (e = ẑ·âb: falling is cheap, climbing is dear) and s(d_WT) below it, C_P = 1 − P. C_WT
//!   depends on the water table, so there is one cost set per water table named by a spring.
//! - **paris2021** (Paris et al. 2021 §4.2): per metre ε + w_dist + w_L·g(d_L/r) + w_F·c_F +
//!   w_π·π, g the smoothstep, π = 1 − P the relative resistance to flow. One cost set. The
//!   user-prescribed paths (`skeleton.forced_links`) cost `forced_link_cost` per metre along
//!   the straight corridor between their key points.
//!
//! Terms are integrated along the edge, never taken at one endpoint. The distance terms use
//! the signed distances of both ends to every surface, computed once per node ([`NodeFields`]):
//! to a plane the signed distance is linear along the edge, so between the points where it
//! crosses 0 or ±d_max the falloff is a cubic in the edge parameter and Simpson's rule on each
//! piece is exact (for gently curved surfaces the linear interpolation is first-order at the
//! scale of an edge). An edge therefore cannot jump over a cheap horizon or a costly band
//! between two ends. The water-table term is split where the edge crosses the water table:
//! the vadose part depends on the direction only, the phreatic part is integrated. 1 − P is a
//! field of unknown shape: Simpson's rule on the ends and the middle. ε > 0 (`cost_floor`)
//! keeps every edge's cost ≥ ε·length > 0 without clamping any term: a zero-cost edge would
//! make Dijkstra's paths arbitrary among free detours.
//!
//! Fractures. Paris et al. write c_F = Σ_k w_k(1 − (n_k·d̂)²) with n_k the normal of family k,
//! while their text says edges parallel to a fracture plane must be the cheap ones; and a sum
//! of quadratic forms in d̂ has a single preferred axis (for three orthogonal families it is
//! constant), so it cannot draw paths along two families. karstgen reads w_k(1 − (n_k·d̂)²) as
//! the *attraction* of family k (1 in its plane, 0 along its normal, w_k scaled so the strongest
//! family has 1) and charges c_F = 1 − max_k of it: the edge follows its best family. KarstNSim's
//! step C_F uses the same plane test: the edge is within family k when its angle to the plane,
//! asin|n_k·d̂|, is below the tolerance τ_k. For a vertical family and a horizontal edge that
//! angle is |θ_E − θ_F| (KarstNSim's azimuth test); a family's dip makes the test 3D. With
//! unequal weights C_F = 1 − (largest relative weight of the matching families).

use glam::DVec3;
use rayon::prelude::*;

use karst_geology::{FractureFamily, Geology, Surface};
use karst_scene::params::{CostModelKind, CostgraphParams};
use karst_scene::{KeyPoint, KeyPointKind, keypoints_of};

use crate::view::CostgraphView;

use crate::falloff::{smoothstep, wyvill};

/// In [`CostModel::sharing`]: the node is above every water table.
pub const ABOVE_EVERY_TABLE: u8 = 1;
/// In [`CostModel::sharing`]: the node is at least d_max below every water table.
pub const DEEP_BELOW_EVERY_TABLE: u8 = 2;

/// One fracture family, prepared for the edge tests.
#[derive(Debug, Clone)]
struct Family {
    normal: DVec3,
    sin_tolerance: f64,
    relative_weight: f64,
}

/// Everything the cost of an edge depends on.
#[derive(Debug, Clone)]
pub struct CostModel {
    kind: CostModelKind,
    params: CostgraphParams,
    geology: Geology,
    inception: Vec<Surface>,
    families: Vec<Family>,
    /// The water table of each cost set (karstnsim2024); empty for paris2021.
    water_tables: Vec<Surface>,
    /// The potential is the same everywhere (no layer, no grid, no potential tree).
    uniform_potential: bool,
    /// paris2021: the straight corridors (ends) of the forced links, `skeleton.forced_links`.
    corridors: Vec<(DVec3, DVec3)>,
}

/// Per-node values the edges share, packed node by node so that reading a neighbour costs one
/// cache miss: position, 1 − P, signed distances to every inception surface, then to the water
/// table of every cost set (positive above).
#[derive(Clone)]
pub struct NodeFields {
    data: Vec<f64>,
    stride: usize,
    surfaces: usize,
    sets: usize,
    /// Per node, a bit per forced-link corridor containing it (`words` u64 per node; none
    /// without forced links).
    corridors: Vec<u64>,
    words: usize,
}

impl NodeFields {
    fn node(&self, i: usize) -> &[f64] {
        &self.data[i * self.stride..(i + 1) * self.stride]
    }

    /// Position of node `i`.
    pub fn position(&self, i: usize) -> DVec3 {
        let n = self.node(i);
        DVec3::new(n[0], n[1], n[2])
    }

    /// Number of nodes.
    pub fn node_count(&self) -> usize {
        self.data.len() / self.stride
    }
}

/// The terms of an edge that do not depend on the cost set.
struct SharedTerms {
    length: f64,
    inception: f64,
    resistance: f64,
    fracture: f64,
}

/// The terms of one edge (each the mean along the edge, before its weight) and its costs.
#[derive(Debug, Clone, Default)]
pub struct EdgeTerms {
    pub length: f64,
    pub inception: f64,
    pub fracture: f64,
    pub resistance: f64,
    /// C_WT per cost set (karstnsim2024).
    pub water_table: Vec<f64>,
    /// Cost per cost set.
    pub cost: Vec<f64>,
    /// Breakpoints of the current edge (reused between edges).
    cuts: Vec<f64>,
}

impl CostModel {
    /// The cost model of the scene's geology, key points, forced links and `[costgraph]`.
    pub fn new(view: &CostgraphView) -> Self {
        let fractures = fracture_families(view);
        let max_weight = fractures.iter().map(|f| f.weight).fold(0.0, f64::max);
        let families = fractures
            .iter()
            .filter(|f| f.weight > 0.0)
            .map(|f| Family {
                normal: f.normal(),
                sin_tolerance: f.tolerance.to_radians().sin(),
                relative_weight: f.weight / max_weight,
            })
            .collect();
        let water_tables = match view.costgraph.model {
            CostModelKind::Paris2021 => Vec::new(),
            CostModelKind::Karstnsim2024 => spring_water_tables(view.geology, view.keypoints),
        };
        CostModel {
            kind: view.costgraph.model,
            params: view.costgraph.clone(),
            geology: view.geology.clone(),
            inception: view.geology.inception_surfaces().cloned().collect(),
            families,
            water_tables,
            corridors: match view.costgraph.model {
                CostModelKind::Paris2021 => forced_corridors(view.keypoints, view.forced_links),
                CostModelKind::Karstnsim2024 => Vec::new(),
            },
            uniform_potential: view.geology.uniform_potential(),
        }
    }

    /// Number of cost sets.
    pub fn set_count(&self) -> usize {
        self.water_tables.len().max(1)
    }

    /// The water table of each cost set (None: paris2021's single set).
    pub fn set_water_tables(&self) -> Vec<Option<String>> {
        match self.kind {
            CostModelKind::Paris2021 => vec![None],
            CostModelKind::Karstnsim2024 if self.water_tables.is_empty() => vec![None],
            CostModelKind::Karstnsim2024 => self.water_tables.iter().map(|w| Some(w.name.clone())).collect(),
        }
    }

    /// Name of the model, as in the scene.
    pub fn name(&self) -> &'static str {
        match self.kind {
            CostModelKind::Paris2021 => "paris2021",
            CostModelKind::Karstnsim2024 => "karstnsim2024",
        }
    }

    /// The weighted terms of the model as (name, weight), in the order [`EdgeTerms::values`]
    /// gives them.
    pub fn terms(&self) -> Vec<(&'static str, f64)> {
        let p = &self.params;
        match self.kind {
            CostModelKind::Karstnsim2024 if self.water_tables.is_empty() => vec![
                ("C_I inception", p.alpha_inception),
                ("C_F fracture", p.alpha_fracture),
                ("C_P potential", p.alpha_potential),
            ],
            CostModelKind::Karstnsim2024 => vec![
                ("C_I inception", p.alpha_inception),
                ("C_F fracture", p.alpha_fracture),
                ("C_WT water table", p.alpha_water_table),
                ("C_P potential", p.alpha_potential),
            ],
            CostModelKind::Paris2021 => vec![
                ("g horizon", p.w_horizon),
                ("c_F fracture", p.w_fracture),
                ("pi resistance", p.w_permeability),
            ],
        }
    }

    /// Smallest and largest possible cost per metre: ε, and ε plus every weight (each term
    /// is at most 1).
    pub fn cost_per_metre_range(&self) -> (f64, f64) {
        let constant = match self.kind {
            CostModelKind::Paris2021 => self.params.w_distance,
            CostModelKind::Karstnsim2024 => 0.0,
        };
        let floor = self.params.cost_floor;
        (floor, floor + constant + self.terms().iter().map(|t| t.1).sum::<f64>())
    }

    /// A lower bound of the cost per metre of every edge in every cost set, from the model's
    /// parameters alone: ε plus each weight times the least its term can be, and the forced
    /// links' cost. A term whose field reaches its cheap end somewhere can be 0 there (on an
    /// inception surface, along the strongest fracture family, falling straight down or along
    /// the water table, at full potential); without surfaces or families the term is 1, and a
    /// uniform potential gives its own value. The searches' A* heuristic is this bound times
    /// the distance, so it never reads the edges' costs (which are made only for the rows the
    /// searches reach: `costs.rs`).
    pub fn least_cost_per_metre(&self) -> f64 {
        let p = &self.params;
        let least_where = |reached: bool| if reached { 0.0 } else { 1.0 };
        let inception = least_where(!self.inception.is_empty());
        let fracture = least_where(!self.families.is_empty());
        let resistance = if self.uniform_potential { self.resistance_at(DVec3::ZERO) } else { 0.0 };
        match self.kind {
            CostModelKind::Paris2021 => {
                let model = p.cost_floor
                    + p.w_distance
                    + p.w_horizon * inception
                    + p.w_fracture * fracture
                    + p.w_permeability * resistance;
                if self.corridors.is_empty() { model } else { model.min(p.forced_link_cost) }
            }
            CostModelKind::Karstnsim2024 => {
                p.cost_floor
                    + p.alpha_inception * inception
                    + p.alpha_fracture * fracture
                    + p.alpha_potential * resistance
            }
        }
    }

    /// The values every edge of a node shares, in parallel.
    pub fn node_fields(&self, points: &[[f64; 3]]) -> NodeFields {
        let (surfaces, sets) = (self.inception.len(), self.water_tables.len());
        let data = points
            .par_iter()
            .flat_map_iter(|p| {
                let at = DVec3::from_array(*p);
                let inception = self.inception.iter().map(move |s| s.signed_distance(at));
                let water_tables = self.water_tables.iter().map(move |w| w.signed_distance(at));
                p.iter().copied().chain([self.resistance_at(at)]).chain(inception).chain(water_tables)
            })
            .collect();
        let words = self.corridors.len().div_ceil(64);
        let radius = self.params.forced_link_radius;
        let corridors = points
            .par_iter()
            .flat_map_iter(|p| {
                let at = DVec3::from_array(*p);
                let mut mask = vec![0u64; words];
                for (c, &(a, b)) in self.corridors.iter().enumerate() {
                    if distance_to_segment(at, a, b) <= radius {
                        mask[c / 64] |= 1 << (c % 64);
                    }
                }
                mask
            })
            .collect();
        NodeFields { data, stride: 4 + surfaces + sets, surfaces, sets, corridors, words }
    }

    /// True when both ends of edge i → j lie in the corridor of the same forced link.
    fn along_forced_link(&self, fields: &NodeFields, i: usize, j: usize) -> bool {
        let w = fields.words;
        let (a, b) = (&fields.corridors[i * w..(i + 1) * w], &fields.corridors[j * w..(j + 1) * w]);
        a.iter().zip(b).any(|(x, y)| x & y != 0)
    }

    /// Fills `out` with the terms and costs of the edge from node `i` to node `j`.
    pub fn edge(&self, fields: &NodeFields, i: usize, j: usize, out: &mut EdgeTerms) {
        out.water_table.clear();
        out.cost.clear();
        let (water_table, cost) = (&mut out.water_table, &mut out.cost);
        let shared = self.edge_with(fields, (i, j), &mut out.cuts, |c_wt, c| {
            water_table.extend(c_wt);
            cost.push(c);
        });
        (out.length, out.inception, out.resistance, out.fracture) =
            (shared.length, shared.inception, shared.resistance, shared.fracture);
    }

    /// The cost of edge i → j in every cost set, into `costs` (one per set), without its
    /// terms: what the searches read ([`crate::Costs`]), the same bits as [`CostModel::edge`].
    #[inline]
    pub fn edge_costs(
        &self,
        fields: &NodeFields,
        (i, j): (usize, usize),
        cuts: &mut Vec<f64>,
        costs: &mut [f64],
    ) {
        let mut set = 0;
        self.edge_with(fields, (i, j), cuts, |_, c| {
            costs[set] = c;
            set += 1;
        });
    }

    /// The terms of edge i → j that every cost set shares; `set_cost(C_WT, cost)` hears each
    /// cost set's cost in order (with its C_WT under karstnsim2024).
    #[inline]
    fn edge_with(
        &self,
        fields: &NodeFields,
        (i, j): (usize, usize),
        cuts: &mut Vec<f64>,
        mut set_cost: impl FnMut(Option<f64>, f64),
    ) -> SharedTerms {
        let (from, to) = (fields.node(i), fields.node(j));
        let (a, b) = (fields.position(i), fields.position(j));
        let length = a.distance(b);
        let direction = (b - a) / length;
        let p = &self.params;
        let (falloff, reach): (fn(f64) -> f64, f64) = match self.kind {
            CostModelKind::Paris2021 => (smoothstep, p.horizon_distance),
            CostModelKind::Karstnsim2024 => (wyvill_of_ratio, p.inception_distance),
        };
        let surfaces = 4..4 + fields.surfaces;
        let inception = mean_of_nearest(&from[surfaces.clone()], &to[surfaces], (reach, falloff), cuts);
        // A uniform potential (no layer, grid or potential tree) is the same at the middle as
        // at the ends: skip its evaluation, keep the same arithmetic (bit-identical).
        let middle = if self.uniform_potential { from[3] } else { self.resistance_at((a + b) * 0.5) };
        let resistance = (from[3] + 4.0 * middle + to[3]) / 6.0;
        let fracture = self.fracture(direction);
        match self.kind {
            CostModelKind::Paris2021 => {
                let mut per_metre = p.cost_floor
                    + p.w_distance
                    + p.w_horizon * inception
                    + p.w_fracture * fracture
                    + p.w_permeability * resistance;
                if fields.words > 0 && self.along_forced_link(fields, i, j) {
                    per_metre = per_metre.min(p.forced_link_cost);
                }
                set_cost(None, length * per_metre);
            }
            CostModelKind::Karstnsim2024 => {
                let shared = p.cost_floor
                    + p.alpha_inception * inception
                    + p.alpha_fracture * fracture
                    + p.alpha_potential * resistance;
                if fields.sets == 0 {
                    set_cost(None, length * shared);
                }
                // Depends on the direction only; acos is dear, so only when an edge has a
                // vadose part (an end at or above a water table), and once for all the sets.
                let tables = 4 + fields.surfaces..4 + fields.surfaces + fields.sets;
                let vadose_part = tables.clone().any(|s| from[s] >= 0.0 || to[s] >= 0.0);
                let vadose = if vadose_part {
                    1.0 - direction.z.clamp(-1.0, 1.0).acos() / std::f64::consts::PI
                } else {
                    f64::NAN
                };
                for s in tables {
                    let c = self.water_table_term((from[s], to[s]), vadose, cuts);
                    set_cost(Some(c), length * (shared + p.alpha_water_table * c));
                }
            }
        }
        SharedTerms { length, inception, resistance, fracture }
    }

    /// Per node, the cases in which its edges cost the same in every cost set: bit
    /// [`ABOVE_EVERY_TABLE`] when it is above every water table, bit [`DEEP_BELOW_EVERY_TABLE`]
    /// when it is at least d_max below every one. An edge whose two ends share a bit costs the
    /// same in every set (C_WT depends on the direction alone above the tables and is the
    /// falloff's constant 1 that deep below them: [`CostModel::edge`] computes the same bits
    /// for every set). Other edges may happen to cost the same too; they are stored apart.
    /// Classifying the nodes once spares testing every set at both ends of every edge.
    pub fn sharing(&self, fields: &NodeFields) -> Vec<u8> {
        let sets = 4 + fields.surfaces..4 + fields.surfaces + fields.sets;
        let reach = self.params.water_table_distance;
        (0..fields.data.len() / fields.stride)
            .into_par_iter()
            .with_min_len(4096)
            .map(|i| {
                let heights = &fields.node(i)[sets.clone()];
                let above = heights.iter().all(|&h| h >= 0.0);
                let deep = heights.iter().all(|&h| h <= -reach);
                (if above { ABOVE_EVERY_TABLE } else { 0 }) | (if deep { DEEP_BELOW_EVERY_TABLE } else { 0 })
            })
            .collect()
    }

    /// 1 − P: KarstNSim's C_P, Paris et al.'s relative resistance π.
    fn resistance_at(&self, p: DVec3) -> f64 {
        1.0 - self.geology.potential(p)
    }

    /// Fracture term of direction `d` (unit).
    fn fracture(&self, d: DVec3) -> f64 {
        match self.kind {
            CostModelKind::Paris2021 => {
                let best = self
                    .families
                    .iter()
                    .map(|f| f.relative_weight * (1.0 - f.normal.dot(d).powi(2)))
                    .fold(0.0, f64::max);
                1.0 - best
            }
            CostModelKind::Karstnsim2024 => {
                let best = self
                    .families
                    .iter()
                    .filter(|f| f.normal.dot(d).abs() < f.sin_tolerance)
                    .map(|f| f.relative_weight)
                    .fold(0.0, f64::max);
                1.0 - best
            }
        }
    }

    /// Mean C_WT along an edge whose ends lie at signed distances `(a, b)` from the water
    /// table: `vadose` above it, s(d_WT) below, split where the edge crosses it. `vadose` is
    /// only read when an end is at or above the table.
    fn water_table_term(&self, (a, b): (f64, f64), vadose: f64, cuts: &mut Vec<f64>) -> f64 {
        let phreatic = |from: f64, to: f64, cuts: &mut Vec<f64>| {
            mean_of_nearest(&[from], &[to], (self.params.water_table_distance, wyvill_of_ratio), cuts)
        };
        match (a >= 0.0, b >= 0.0) {
            (true, true) => vadose,
            (false, false) => phreatic(a, b, cuts),
            (true, false) => {
                let t = a / (a - b);
                t * vadose + (1.0 - t) * phreatic(0.0, b, cuts)
            }
            (false, true) => {
                let t = a / (a - b);
                t * phreatic(a, 0.0, cuts) + (1.0 - t) * vadose
            }
        }
    }
}

/// The ends of every forced link (`skeleton.forced_links`), at the scene's key point positions.
fn forced_corridors(keypoints: &[KeyPoint], forced_links: &[[String; 2]]) -> Vec<(DVec3, DVec3)> {
    let at = |name: &str| keypoints.iter().find(|k| k.name == name).map(|k| DVec3::from_array(k.position));
    forced_links.iter().filter_map(|[a, b]| Some((at(a)?, at(b)?))).collect()
}

/// Distance from `p` to the segment a–b.
fn distance_to_segment(p: DVec3, a: DVec3, b: DVec3) -> f64 {
    let ab = b - a;
    let t =
        if ab.length_squared() > 0.0 { ((p - a).dot(ab) / ab.length_squared()).clamp(0.0, 1.0) } else { 0.0 };
    p.distance(a + ab * t)
}

/// The scene's fracture families, or the joint sets assumed when it has none and
/// `costgraph.assumed_joints` holds ([`crate::joints`]).
pub fn fracture_families(view: &CostgraphView) -> Vec<FractureFamily> {
    if view.geology.fractures.is_empty() && view.costgraph.assumed_joints {
        crate::joints::assumed(view.domain, view.terrain).to_vec()
    } else {
        view.geology.fractures.clone()
    }
}

/// Water tables named by springs, in [geology.water_tables] order.
fn spring_water_tables(geology: &Geology, keypoints: &[KeyPoint]) -> Vec<Surface> {
    let named: Vec<&str> =
        keypoints_of(keypoints, KeyPointKind::Spring).filter_map(|(_, k)| k.water_table.as_deref()).collect();
    geology.water_tables.iter().filter(|w| named.contains(&w.name.as_str())).cloned().collect()
}

/// KarstNSim's falloff as a function of x = d / d_max.
fn wyvill_of_ratio(x: f64) -> f64 {
    wyvill(x, 1.0)
}

/// Mean over the edge of falloff(d / reach), d the distance to the nearest of some surfaces,
/// given the signed distances `a` and `b` of the edge's ends to each surface. The signed
/// distance to a plane is linear along the edge; between the points where it crosses 0 or
/// ±reach the falloff of one surface is a cubic in t, which Simpson's rule integrates exactly.
/// Without surfaces the term is saturated (1).
#[inline]
fn mean_of_nearest(a: &[f64], b: &[f64], along: (f64, fn(f64) -> f64), cuts: &mut Vec<f64>) -> f64 {
    // No surface, or both ends at least `reach` from every surface on the same side: the
    // distance to each stays ≥ reach along the edge (it is linear), the falloff is 1 everywhere,
    // and so is its mean (the general sum gives exactly 1.0 too: one piece, (1 + 4 + 1)/6).
    // Most edges are there; this test is inlined, the integration is not.
    let reach = along.0;
    if a.iter().zip(b).all(|(&sa, &sb)| (sa >= reach && sb >= reach) || (sa <= -reach && sb <= -reach)) {
        return 1.0;
    }
    integrate_nearest(a, b, along, cuts)
}

/// [`mean_of_nearest`] on an edge that comes within reach of some surface.
#[inline(never)]
fn integrate_nearest(
    a: &[f64],
    b: &[f64],
    (reach, falloff): (f64, fn(f64) -> f64),
    cuts: &mut Vec<f64>,
) -> f64 {
    cuts.clear();
    cuts.extend([0.0, 1.0]);
    for (&sa, &sb) in a.iter().zip(b) {
        for level in [0.0, reach, -reach] {
            if (sa - level) * (sb - level) < 0.0 {
                cuts.push((sa - level) / (sa - sb));
            }
        }
    }
    cuts.sort_unstable_by(f64::total_cmp);
    let value = |t: f64| {
        let d = a.iter().zip(b).map(|(&sa, &sb)| (sa + (sb - sa) * t).abs()).fold(f64::INFINITY, f64::min);
        falloff(d / reach)
    };
    let mut sum = 0.0;
    let mut left = value(cuts[0]);
    for w in cuts.windows(2) {
        let right = value(w[1]);
        sum += (w[1] - w[0]) * (left + 4.0 * value((w[0] + w[1]) * 0.5) + right) / 6.0;
        left = right;
    }
    sum
}

impl EdgeTerms {
    /// The term values in the order of [`CostModel::terms`] for cost set `set`, and how many
    /// there are.
    pub fn values(&self, set: usize) -> ([f64; 4], usize) {
        match self.water_table.get(set) {
            Some(&wt) => ([self.inception, self.fracture, wt, self.resistance], 4),
            None => ([self.inception, self.fracture, self.resistance, 0.0], 3),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::path::Path;

    use karst_scene::{Scene, SceneView};

    fn model(extra: &str) -> CostModel {
        let text = format!(
            r#"
name = "t"
[domain]
min = [0, 0, 0]
max = [100, 100, 100]
[terrain]
kind = "plane"
elevation = 100
[[geology.water_tables]]
name = "wt"
elevation = 20
[[geology.horizons]]
name = "h"
elevation = 50
[[keypoints]]
name = "a"
kind = "sink"
position = [10, 10, 90]
[[keypoints]]
name = "s"
kind = "spring"
position = [90, 90, 20]
water_table = "wt"
{extra}
"#
        );
        CostModel::new(&CostgraphView::of(&Scene::parse(&text, Path::new("t.toml")).unwrap()))
    }

    fn cost(model: &CostModel, a: DVec3, b: DVec3) -> EdgeTerms {
        let fields = model.node_fields(&[a.to_array(), b.to_array()]);
        let mut out = EdgeTerms::default();
        model.edge(&fields, 0, 1, &mut out);
        out
    }

    #[test]
    fn falling_is_cheap_and_climbing_is_dear_above_the_water_table() {
        let m = model("");
        let (hi, lo) = (DVec3::new(50.0, 50.0, 80.0), DVec3::new(50.0, 50.0, 70.0));
        assert!(cost(&m, hi, lo).water_table[0].abs() < 1e-12);
        assert!((cost(&m, lo, hi).water_table[0] - 1.0).abs() < 1e-12);
        let side = cost(&m, hi, DVec3::new(60.0, 50.0, 80.0));
        assert!((side.water_table[0] - 0.5).abs() < 1e-12);
    }

    #[test]
    fn cost_is_integrated_along_the_edge() {
        let m = model("[costgraph]\ninception_distance = 10.0");
        // Both ends 10 m from the horizon (term 1), the middle on it (term 0).
        let e = cost(&m, DVec3::new(50.0, 50.0, 40.0), DVec3::new(50.0, 50.0, 60.0));
        assert!(e.inception < 0.8, "{}", e.inception);
        // Exact mean of s over the edge: ∫0^1 1 − (1 − x)³ dx = 3/4 on each half.
        assert!((e.inception - 0.75).abs() < 0.01, "{}", e.inception);
        assert!(e.cost[0] > 0.0);
    }

    #[test]
    fn crossing_the_water_table_splits_the_term() {
        let m = model("[costgraph]\nwater_table_distance = 10.0");
        // Straight down from 5 m above to 5 m below: half vadose (0), half phreatic.
        let e = cost(&m, DVec3::new(50.0, 50.0, 25.0), DVec3::new(50.0, 50.0, 15.0));
        // Mean of s over d ∈ [0, 5] with d_max = 10: 2·∫₀^½ 1 − (1 − x)³ dx = 2·(½ − 15/64).
        let phreatic_mean = 2.0 * (0.5 - 15.0 / 64.0);
        assert!((e.water_table[0] - 0.5 * phreatic_mean).abs() < 1e-3, "{}", e.water_table[0]);
    }

    #[test]
    fn every_cost_is_positive_even_when_every_term_vanishes() {
        let m = model("[costgraph]\nalpha_inception = 0.0\nalpha_fracture = 0.0\nalpha_potential = 0.0");
        let e = cost(&m, DVec3::new(50.0, 50.0, 80.0), DVec3::new(50.0, 50.0, 70.0));
        assert_eq!(e.water_table[0], 0.0);
        assert!((e.cost[0] - 10.0 * 0.01).abs() < 1e-12);
    }

    #[test]
    fn edges_along_a_fracture_family_are_cheap() {
        let fractures = "[[geology.fractures]]\nname = \"n030\"\nazimuth = 30.0\ntolerance = 5.0\n";
        let m = model(fractures);
        let along = |deg: f64| {
            let (s, c) = deg.to_radians().sin_cos();
            cost(&m, DVec3::new(50.0, 50.0, 80.0), DVec3::new(50.0 + 5.0 * s, 50.0 + 5.0 * c, 80.0)).fracture
        };
        assert_eq!(along(32.0), 0.0);
        assert_eq!(along(212.0), 0.0);
        assert_eq!(along(40.0), 1.0);
        let paris = model(&format!("{fractures}[costgraph]\nmodel = \"paris2021\""));
        let e = |deg: f64| {
            let (s, c) = deg.to_radians().sin_cos();
            cost(&paris, DVec3::new(50.0, 50.0, 80.0), DVec3::new(50.0 + 5.0 * s, 50.0 + 5.0 * c, 80.0))
                .fracture
        };
        assert!(e(30.0) < 1e-12 && (e(120.0) - 1.0).abs() < 1e-12 && e(60.0) > e(40.0));
    }
}
