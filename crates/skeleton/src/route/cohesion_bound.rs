//! The phreatic A*'s heuristic under cohesion (`karstnsim.rs`): a lower bound of the cost from
//! a sample to the spring that knows where the network is, so that the search does not explore
//! as if every metre could be paid at the cohesion discount.
//!
//! ## The costs it bounds
//! In a phreatic leg an edge e costs its cost c_e in the spring's cost set, times
//! `inherited_cost` when an earlier phase's conduit uses it, times P = `cohesion_phreatic` when
//! it is *used*, i.e. it is an edge of a leg chosen earlier in the phase or the reverse of one
//! (`karstnsim::mark_used`). Both ends of a used edge are therefore samples of those legs'
//! paths: call that set N (the network so far). With α the least cost per metre of the cost set
//! times `inherited_cost` (at most 1, so α bounds inherited edges too), every edge u → v costs
//! at least α·|u − v| and a used one at least α·P·|u − v|. With P ≥ 1 no edge is cheaper than
//! α per metre and the bound below is α·|v − t|.
//!
//! ## The bound (P < 1)
//! For a search towards t:
//!
//! h(v) = α · min(|v − t|, (1 − P)·(L(v) + D) + P·|v − t|)
//!
//! where L(v) = min(R, d(v, N)) (R the reach of [`NetworkDistance`]; L is 1-Lipschitz, zero on
//! N and at most d(v, N)) and D = d(t, N) (+∞ while N is empty). The old heuristic,
//! α·P·|v − t|, assumed the whole way could be discounted; this one charges full price for the
//! way to the network and from it.
//!
//! *Admissible.* A path from v to t without used edges costs at least α·|v − t|. Otherwise let
//! a be the start of its first used edge and b the end of its last one, both in N: the path pays
//! at least α per metre before a and after b, at least α·P per metre in between, so
//! cost ≥ α·(|v − a| + P·|a − b| + |b − t|) ≥ α·((1 − P)·(|v − a| + |b − t|) + P·|v − t|) (as
//! |a − b| ≥ |v − t| − |v − a| − |b − t|) ≥ α·((1 − P)·(L(v) + D) + P·|v − t|).
//!
//! *Consistent* (h(u) ≤ cost(u → v) + h(v) on every edge, and h(t) = 0; A* then settles every
//! sample at its least cost, so the spring is reached at the least cost, as by Dijkstra). Both
//! terms of the min change by at most α per metre moved (|v − t| is 1-Lipschitz, and
//! (1 − P)·L + P·|v − t| is (1 − P) + P = 1-Lipschitz), so their min does too: an unused edge,
//! costing at least α·|u − v|, satisfies the inequality. The ends of a used edge are in N, where
//! L = 0 and the second term is the smaller (|v − t| ≥ d(t, N) = D, so
//! (1 − P)·D + P·|v − t| ≤ |v − t|): h = α·((1 − P)·D + P·|v − t|) there, which changes by at
//! most α·P·|u − v| along the edge, no more than it costs.
//!
//! Only the order in which samples are settled changes, and fewer are settled; a sample's least
//! cost and the path the tree keeps for it (its first relaxation at that cost) are those of
//! the old heuristic unless two paths cost exactly the same.
//!
//! ## With the least costs to the spring
//! When many legs go to one spring, `spring_distance.rs` computes T(v) = d(v, t), the least
//! cost from v to t on the phase's costs before cohesion. With T̃(v) = max(T(v), α·|v − t|)
//! (both lower bounds of d(v, t), both consistent on those costs, so their max is too) the
//! bound becomes
//!
//! h(v) = min(T̃(v), P·T̃(v) + (1 − P)·α·(L(v) + D))
//!
//! which is never below the bound above (T̃ ≥ α·|v − t|) and equals T̃ while the network is
//! empty (D = +∞). *Admissible:* a path without used edges costs at least d(v, t) ≥ T̃(v);
//! otherwise it pays every edge at least P times its cost, and the parts before its first used
//! edge and after its last one in full: cost ≥ P·d(v, t) + (1 − P)·α·(|v − a| + |b − t|) ≥
//! P·T̃(v) + (1 − P)·α·(L(v) + D). *Consistent:* on an unused edge u → v (cost c ≥ α·|u − v|)
//! each term of the min grows by at most c (T̃ by consistency, the second by P·c + (1 − P)·c as
//! L is 1-Lipschitz); on a used edge (cost P·c, both ends in N, L = 0) h = P·T̃ + (1 − P)·α·D
//! at both ends (T̃(v) ≥ α·|v − t| ≥ α·D for v in N), which changes by at most P·c. With
//! P ≥ 1 it is T̃ alone.
//!
//! ## The distance to the network
//! [`NetworkDistance`] keeps L for every sample, updated as legs join the network: each new
//! network sample lowers L of the samples within R of it, found through a uniform grid of the
//! samples; a grid cell whose samples' largest L is not above the cell's distance to the new
//! sample is skipped, so a leg along the existing network costs little. Samples farther than R
//! keep L = R: the bound is weaker there, never wrong. R trades the bound's strength far from
//! the network against the cost of the updates, proportional to the samples within R of each
//! network sample: R is the radius holding 32,768 samples at their mean density (on the peer
//! scene, larger radii settled fewer samples but their updates grew faster than the searches
//! shrank: the trade-off measured in BENCHMARKS.md).

use glam::DVec3;

/// Wanted samples per grid cell.
const SAMPLES_PER_CELL: f64 = 16.0;

/// Samples in a ball of radius R at the samples' mean density: what adding one network sample
/// may cost at most, whatever the sampling density.
const SAMPLES_IN_REACH: f64 = 32768.0;

/// L(v) = min(R, d(v, N)) for every sample v, as the network N grows.
pub struct NetworkDistance<'s> {
    positions: &'s [[f64; 3]],
    reach: f64,
    lo: DVec3,
    cell: f64,
    dims: [usize; 3],
    /// `starts[c]..starts[c + 1]` index the samples of cell c in `order`.
    starts: Vec<u32>,
    order: Vec<u32>,
    /// Per sample: min(R, distance to the network).
    within: Vec<f64>,
    /// Per cell: the largest `within` of its samples (0 for an empty cell).
    farthest: Vec<f64>,
    /// The network's samples' positions (one per distinct position).
    members: Vec<DVec3>,
    /// Rounding allowance on a cell's distance, metres (cells are found by rounded divisions).
    margin: f64,
}

/// The samples' bounding box and its volume (at least 1 m per axis).
fn extent(positions: &[[f64; 3]]) -> (DVec3, DVec3, f64) {
    let lo = positions.iter().fold(DVec3::INFINITY, |m, p| m.min(DVec3::from_array(*p)));
    let hi = positions.iter().fold(DVec3::NEG_INFINITY, |m, p| m.max(DVec3::from_array(*p)));
    let span = (hi - lo).max(DVec3::ZERO);
    (lo, hi, span.x.max(1.0) * span.y.max(1.0) * span.z.max(1.0))
}

impl<'s> NetworkDistance<'s> {
    /// An empty network over `positions`, with the reach R of a ball holding
    /// [`SAMPLES_IN_REACH`] samples at their mean density (the update's cost is bounded, and
    /// the same scene sampled more finely keeps a shorter reach: 540 m at 5 M samples on the
    /// regional scene, 910 m at 1 M, 155 m on the 1 M peer scene).
    pub fn new(positions: &'s [[f64; 3]]) -> Self {
        let (_, _, volume) = extent(positions);
        let per_sample = volume / positions.len().max(1) as f64;
        Self::with_reach(
            positions,
            (3.0 * SAMPLES_IN_REACH * per_sample / (4.0 * std::f64::consts::PI)).cbrt(),
        )
    }

    /// An empty network over `positions`, distances known up to `reach` metres.
    pub fn with_reach(positions: &'s [[f64; 3]], reach: f64) -> Self {
        let (lo, hi, volume) = extent(positions);
        let span = (hi - lo).max(DVec3::ZERO);
        let cell =
            (volume * SAMPLES_PER_CELL / positions.len().max(1) as f64).cbrt().max(reach / 8.0).max(1e-6);
        let dims = (span / cell).to_array().map(|s| s.floor() as usize + 1);
        let mut field = NetworkDistance {
            positions,
            reach,
            lo,
            cell,
            dims,
            starts: Vec::new(),
            order: Vec::new(),
            within: vec![reach; positions.len()],
            farthest: Vec::new(),
            members: Vec::new(),
            margin: 1e-9 * (span.max_element() + lo.abs().max(hi.abs()).max_element()),
        };
        field.bucket();
        field
    }

    /// Sorts the samples into their cells (counting sort).
    fn bucket(&mut self) {
        let cells = self.dims.iter().product::<usize>();
        let keys: Vec<u32> =
            self.positions.iter().map(|p| self.index(self.cell_of(DVec3::from_array(*p))) as u32).collect();
        let mut starts = vec![0u32; cells + 1];
        for &c in &keys {
            starts[c as usize + 1] += 1;
        }
        for c in 0..cells {
            starts[c + 1] += starts[c];
        }
        let mut next = starts.clone();
        let mut order = vec![0u32; keys.len()];
        for (v, &c) in keys.iter().enumerate() {
            order[next[c as usize] as usize] = v as u32;
            next[c as usize] += 1;
        }
        self.farthest =
            (0..cells).map(|c| if starts[c] < starts[c + 1] { self.reach } else { 0.0 }).collect();
        self.starts = starts;
        self.order = order;
    }

    fn cell_of(&self, p: DVec3) -> [usize; 3] {
        let at = (p - self.lo) / self.cell;
        std::array::from_fn(|a| (at[a].max(0.0) as usize).min(self.dims[a] - 1))
    }

    fn index(&self, [x, y, z]: [usize; 3]) -> usize {
        (z * self.dims[1] + y) * self.dims[0] + x
    }

    /// min(R, distance from sample `v` to the network).
    #[inline]
    pub fn at(&self, v: usize) -> f64 {
        self.within[v]
    }

    /// The exact distance from `p` to the network, +∞ while it is empty.
    pub fn exact(&self, p: DVec3) -> f64 {
        self.members.iter().map(|m| m.distance_squared(p)).fold(f64::INFINITY, f64::min).sqrt()
    }

    /// Adds the samples `nodes` to the network.
    pub fn add(&mut self, nodes: &[usize]) {
        for &v in nodes {
            // A sample at distance 0 of the network adds nothing to any distance.
            if self.within[v] > 0.0 {
                self.add_point(DVec3::from_array(self.positions[v]));
            }
        }
    }

    /// Lowers L within R of `p`, a new network sample.
    fn add_point(&mut self, p: DVec3) {
        self.members.push(p);
        let first = self.cell_of(p - DVec3::splat(self.reach));
        let last = self.cell_of(p + DVec3::splat(self.reach));
        // One more cell on each side: the cells of p ± R are found by rounded divisions.
        let dims = self.dims;
        let range = |a: usize| first[a].saturating_sub(1)..=(last[a] + 1).min(dims[a] - 1);
        for z in range(2) {
            for y in range(1) {
                for x in range(0) {
                    let c = self.index([x, y, z]);
                    let gap = (self.gap([x, y, z], p) - self.margin).max(0.0);
                    if gap < self.farthest[c] {
                        self.lower_cell(c, p);
                    }
                }
            }
        }
    }

    /// The distance from `p` to the box of cell `at`.
    fn gap(&self, at: [usize; 3], p: DVec3) -> f64 {
        let low = self.lo + DVec3::from_array(at.map(|i| i as f64)) * self.cell;
        let outside = (low - p).max(p - low - DVec3::splat(self.cell)).max(DVec3::ZERO);
        outside.length()
    }

    /// Lowers L of the samples of cell `c` to their distance to `p` where that is smaller.
    fn lower_cell(&mut self, c: usize, p: DVec3) {
        let mut farthest: f64 = 0.0;
        for &v in &self.order[self.starts[c] as usize..self.starts[c + 1] as usize] {
            let v = v as usize;
            let d2 = DVec3::from_array(self.positions[v]).distance_squared(p);
            if d2 < self.within[v] * self.within[v] {
                self.within[v] = d2.sqrt().min(self.within[v]);
            }
            farthest = farthest.max(self.within[v]);
        }
        self.farthest[c] = farthest;
    }
}

/// The heuristic h of one phreatic search (module docs).
pub struct CohesionBound<'a> {
    pub positions: &'a [[f64; 3]],
    /// α: the least cost per metre of any edge.
    pub per_metre: f64,
    /// P, the cohesion factor of used edges.
    pub factor: f64,
    /// The network so far; None: the plain bound α·min(P, 1)·|v − t| (no distance kept).
    pub network: Option<&'a NetworkDistance<'a>>,
    pub target: usize,
    /// T(v), the least cost from every sample to the target before cohesion
    /// (`spring_distance.rs`), when it was computed: the bound then uses it in place of
    /// α·|v − t| (module docs, "With the least costs to the spring").
    pub to_spring: Option<&'a [f64]>,
}

impl CohesionBound<'_> {
    /// The heuristic as a function of the sample.
    pub fn heuristic(&self) -> impl Fn(usize) -> f64 + '_ {
        let goal = DVec3::from_array(self.positions[self.target]);
        let direct = move |v: usize| DVec3::from_array(self.positions[v]).distance(goal);
        let p = self.factor.min(1.0);
        let network = self.network.filter(|_| p < 1.0);
        // D = d(t, N), once per search.
        let from_target = network.map_or(f64::INFINITY, |n| n.exact(goal));
        move |v: usize| {
            let straight = direct(v);
            match (network, self.to_spring) {
                (None, None) => self.per_metre * p * straight,
                (Some(n), None) => {
                    let via = (1.0 - p) * (n.at(v) + from_target) + p * straight;
                    self.per_metre * straight.min(via)
                }
                (network, Some(to_spring)) => {
                    let least = to_spring[v].max(self.per_metre * straight);
                    match network {
                        None => p * least,
                        Some(n) => {
                            least.min(p * least + (1.0 - p) * self.per_metre * (n.at(v) + from_target))
                        }
                    }
                }
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::modes::karstnsim::mark_used;
    use crate::route::edge_set::EdgeSet;
    use crate::route::search::{Cohesive, EdgeCosts, astar_to_set, dijkstra, min_cost_per_metre};
    use crate::route::spring_distance::{InEdges, costs_to};
    use karst_costgraph::CostGraph;
    use karst_scene::rng::Random;

    fn points(rng: &mut Random, n: usize) -> Vec<[f64; 3]> {
        (0..n).map(|_| [rng.range(0.0, 100.0), rng.range(0.0, 80.0), rng.range(0.0, 20.0)]).collect()
    }

    /// Each point joined to its 10 nearest, at 1–3 times the length.
    fn neighbour_graph(rng: &mut Random, positions: &[[f64; 3]]) -> CostGraph {
        let at = |v: usize| DVec3::from_array(positions[v]);
        let lists = (0..positions.len())
            .map(|u| {
                let mut near: Vec<usize> = (0..positions.len()).filter(|&v| v != u).collect();
                near.sort_by(|&a, &b| at(u).distance(at(a)).total_cmp(&at(u).distance(at(b))));
                near[..10]
                    .iter()
                    .map(|&v| (v as u32, (at(u).distance(at(v)) * rng.range(1.0, 3.0)) as f32))
                    .collect()
            })
            .collect();
        CostGraph::from_lists(lists)
    }

    #[test]
    fn the_distance_is_the_capped_distance_to_the_network() {
        let mut rng = Random::stream(3, "test", "network-distance");
        let positions = points(&mut rng, 3000);
        let reach = 12.0;
        let mut field = NetworkDistance::with_reach(&positions, reach);
        let mut network: Vec<usize> = Vec::new();
        for batch in 0..4 {
            let nodes: Vec<usize> = (0..5 + 20 * batch).map(|_| rng.index(positions.len())).collect();
            field.add(&nodes);
            network.extend(&nodes);
            let at = |v: usize| DVec3::from_array(positions[v]);
            let nearest = |p: DVec3| network.iter().map(|&m| at(m).distance(p)).fold(f64::INFINITY, f64::min);
            for v in 0..positions.len() {
                assert_eq!(field.at(v), nearest(at(v)).min(reach), "sample {v} after batch {batch}");
            }
            let p = DVec3::new(150.0, -20.0, 40.0);
            assert_eq!(field.exact(p), nearest(p));
        }
    }

    #[test]
    fn the_bound_is_consistent_and_astar_finds_dijkstras_paths() {
        let mut rng = Random::stream(4, "test", "cohesion-bound");
        let positions = points(&mut rng, 700);
        let graph = neighbour_graph(&mut rng, &positions);
        let per_metre = min_cost_per_metre(&graph, &positions);
        let factor = 0.3;
        let mut used = EdgeSet::new(graph.edge_count());
        let mut field = NetworkDistance::with_reach(&positions, 15.0);
        let targets = [3, 250, 511, 698];
        let in_edges = InEdges::of(&graph);
        let plain = graph.direct().expect("graph costs");
        let to_springs: Vec<Vec<f64>> = targets
            .iter()
            .map(|&t| costs_to(&plain, &in_edges, t, &mut Vec::new()).expect("stored costs"))
            .collect();
        for (round, (source, target)) in [(10, 600), (42, 17), (300, 5)].into_iter().enumerate() {
            let costs = Cohesive { base: &graph, used: &used, factor };
            for (t, to_spring) in targets.into_iter().zip(&to_springs) {
                let bound = |to_spring| CohesionBound {
                    positions: &positions,
                    per_metre,
                    factor,
                    network: Some(&field),
                    target: t,
                    to_spring,
                };
                let (straight, exact_bound) = (bound(None), bound(Some(to_spring)));
                let (coarse, h) = (straight.heuristic(), exact_bound.heuristic());
                for (h, name) in [(&coarse, "straight line"), (&h, "least costs")] {
                    assert_eq!(h(t), 0.0);
                    for u in 0..positions.len() {
                        costs.for_each_out(u, &mut |_, v, c| {
                            assert!(
                                h(u) <= c + h(v) + 1e-9,
                                "{name}, round {round}, edge {u} → {v}: {} > {c} + {}",
                                h(u),
                                h(v)
                            );
                        });
                    }
                    for s in [0, 77, 444] {
                        let exact = dijkstra(&costs, s, &[t]);
                        let (guided, _) = astar_to_set((&costs, None), s, h, |v| v == t);
                        assert_eq!(guided.cost(t), exact.cost(t), "{name}, round {round}, {s} → {t}");
                        assert_eq!(guided.path(t), exact.path(t), "{name}, round {round}, {s} → {t}");
                    }
                }
                // The least costs never weaken the bound, and strengthen it somewhere.
                assert!((0..positions.len()).all(|v| h(v) >= coarse(v)));
                assert!((0..positions.len()).any(|v| h(v) > 1.5 * coarse(v)), "round {round}, {t}");
            }
            // The network grows by the least-cost path of this round, as a leg joins it.
            let tree = dijkstra(&costs, source, &[target]);
            let (path, edges) = (tree.path(target).expect("connected"), tree.edges(target));
            mark_used(&graph, &edges, &mut used);
            field.add(&path);
        }
        assert!((0..graph.edge_count()).filter(|&e| used.contains(e)).count() > 10);
    }

    #[test]
    fn without_a_discount_the_bound_is_the_straight_line() {
        let mut rng = Random::stream(5, "test", "cohesion-bound");
        let positions = points(&mut rng, 50);
        let mut field = NetworkDistance::with_reach(&positions, 10.0);
        field.add(&[1, 2, 3]);
        for (factor, network) in [(1.0, Some(&field)), (1.5, Some(&field)), (0.4, None)] {
            let bound = CohesionBound {
                positions: &positions,
                per_metre: 2.0,
                factor,
                network,
                target: 7,
                to_spring: None,
            };
            let h = bound.heuristic();
            let straight = DVec3::from_array(positions[9]).distance(DVec3::from_array(positions[7]));
            assert_eq!(h(9), 2.0 * factor.min(1.0) * straight);
        }
    }
}
