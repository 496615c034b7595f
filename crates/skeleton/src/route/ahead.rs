//! Rows costed ahead of a search, on a core the routing leaves idle.
//!
//! The cost graph costs a row the first time a search reads it (karst_costgraph's `costs.rs`),
//! on the searching thread: a large share of a KarstNSim leg's time on the peer scene of issue 21
//! (BENCHMARKS.md).
//! The legs of one sink run in parallel, but most sinks have one long leg, so one core searches
//! while the other waits. [`Ahead`] gives that core the rows the search will read next: every
//! [`HINT_EVERY`] settled nodes the search hands over the [`HINTED`] unsettled nodes of least
//! key in its heap ([`crate::route::search::RadixHeap::lowest`]), and a helper thread costs their rows.
//!
//! A consistent A* settles every node whose key is below the target's, so a node of the heap's
//! lowest keys is nearly always settled later: what the helper costs is what the search would
//! have costed itself, except the last hint of each search (at most [`HINTED`] rows: the helper
//! drops the hints of a finished search). Only rows nobody has begun are costed ahead, and a
//! row's costs are the same bits whichever thread makes them, so the routes do not change.

use std::sync::{Condvar, Mutex};

use karst_costgraph::CostGraph;

/// Settled nodes between two hints of a search.
pub const HINT_EVERY: usize = 64;
/// Nodes per hint.
pub const HINTED: usize = 512;

/// A helper that costs the rows searches on `graph` hint at.
pub struct Ahead<'g> {
    graph: &'g CostGraph,
    hints: Mutex<Hints>,
    wake: Condvar,
}

/// The nodes whose rows to cost next, and whether the routing is over.
#[derive(Default)]
struct Hints {
    nodes: Vec<u32>,
    /// The helper waits for hints.
    waiting: bool,
    over: bool,
}

impl<'g> Ahead<'g> {
    /// Runs `work` with rows costed ahead of its searches on `graph` by a thread of their own,
    /// when the pool has more than one thread and some row is still to cost (else `work` runs
    /// alone, with None: on the regional scene, whose rows are all costed before the least
    /// costs to the springs, an idle helper woken at every hint slowed the routing down).
    pub fn run<R>(graph: &'g CostGraph, work: impl FnOnce(Option<&Ahead<'g>>) -> R) -> R {
        if rayon::current_num_threads() < 2 || graph.every_row_costed() {
            return work(None);
        }
        let ahead = Ahead { graph, hints: Mutex::new(Hints::default()), wake: Condvar::new() };
        std::thread::scope(|scope| {
            scope.spawn(|| ahead.serve());
            // Ends the helper however `work` ends (an error, a panic): the scope waits for it.
            let _over = Over(&ahead);
            work(Some(&ahead))
        })
    }

    /// Whether searches on these costs can hint: they read `graph`'s rows.
    pub fn serves(&self, graph: &CostGraph) -> bool {
        std::ptr::eq(self.graph, graph)
    }

    /// The nodes whose rows a search reads next, least key first; they replace any nodes of an
    /// earlier hint not costed yet. `nodes` is left empty for the next hint.
    pub fn hint(&self, nodes: &mut Vec<u32>) {
        let mut hints = self.hints.lock().unwrap_or_else(|e| e.into_inner());
        let waiting = hints.waiting;
        std::mem::swap(&mut hints.nodes, nodes);
        nodes.clear();
        drop(hints);
        if waiting {
            self.wake.notify_one();
        }
    }

    /// Drops the hints not costed yet (their search is over).
    pub fn forget(&self) {
        self.hints.lock().unwrap_or_else(|e| e.into_inner()).nodes.clear();
    }

    /// The helper: costs the hinted rows until the routing is over.
    fn serve(&self) {
        let mut batch = Vec::new();
        loop {
            {
                let mut hints = self.hints.lock().unwrap_or_else(|e| e.into_inner());
                while hints.nodes.is_empty() && !hints.over {
                    hints.waiting = true;
                    hints = self.wake.wait(hints).unwrap_or_else(|e| e.into_inner());
                    hints.waiting = false;
                }
                if hints.over {
                    return;
                }
                std::mem::swap(&mut hints.nodes, &mut batch);
            }
            for &node in &batch {
                self.graph.cost_row_ahead(node as usize);
            }
            batch.clear();
        }
    }
}

/// Tells the helper the routing is over when dropped.
struct Over<'a, 'g>(&'a Ahead<'g>);

impl Drop for Over<'_, '_> {
    fn drop(&mut self) {
        self.0.hints.lock().unwrap_or_else(|e| e.into_inner()).over = true;
        self.0.wake.notify_one();
    }
}

#[cfg(test)]
mod tests {
    use std::path::Path;

    use glam::DVec3;
    use karst_costgraph::Costing;
    use karst_scene::{Scene, SceneView};

    use super::*;
    use crate::route::search::{EdgeCosts, astar_to_set, min_cost_per_metre};

    const SCENE: &str = r#"
name = "ahead"
seed = 5
[domain]
min = [0, 0, 0]
max = [400, 300, 120]
[terrain]
kind = "plane"
elevation = 118
[[geology.water_tables]]
name = "wt"
elevation = 30
[[keypoints]]
name = "sink"
kind = "sink"
position = [20, 20, 110]
[[keypoints]]
name = "spring"
kind = "spring"
position = [380, 280, 30]
water_table = "wt"
[sampling]
radius = 8.0
[costgraph]
k = 20
"#;

    /// A* between the scene's two key points on a graph costed on demand, in a pool of
    /// `threads`, with a helper costing rows ahead when there are two: the path, its cost's
    /// bits, the nodes the search reached, and the graph.
    fn search(threads: usize) -> (Vec<usize>, u64, usize, CostGraph) {
        let scene = Scene::parse(SCENE, Path::new("ahead.toml")).unwrap();
        let samples = karst_sampling::build(&karst_sampling::SamplingView::of(&scene)).unwrap();
        let costs = karst_costgraph::CostgraphView::of(&scene);
        let graph = karst_costgraph::build(&costs, &samples).unwrap();
        graph.cost_from(&costs, &samples.positions, Costing::OnDemand).unwrap();
        let (source, target) = (samples.keypoint_sample(0).unwrap(), samples.keypoint_sample(1).unwrap());
        let pool = rayon::ThreadPoolBuilder::new().num_threads(threads).build().unwrap();
        let (path, cost, reached) = pool.install(|| {
            let per_metre = min_cost_per_metre(&graph, &samples.positions);
            let goal = DVec3::from_array(samples.positions[target]);
            let h = |v: usize| DVec3::from_array(samples.positions[v]).distance(goal) * per_metre;
            Ahead::run(&graph, |ahead| {
                assert_eq!(ahead.is_some(), threads > 1);
                let (tree, _) = astar_to_set((&graph as &dyn EdgeCosts, ahead), source, h, |v| v == target);
                let reached = (0..graph.node_count()).filter(|&v| tree.cost(v).is_finite()).count();
                (tree.path(target).unwrap(), tree.cost(target).to_bits(), reached)
            })
        });
        (path, cost, reached, graph)
    }

    #[test]
    fn no_helper_when_every_row_is_costed() {
        let graph = CostGraph::from_lists(vec![vec![(1, 1.0)], vec![(0, 1.0)]]);
        let pool = rayon::ThreadPoolBuilder::new().num_threads(2).build().unwrap();
        assert!(pool.install(|| Ahead::run(&graph, |ahead| ahead.is_none())));
    }

    #[test]
    fn rows_costed_ahead_change_no_path_and_no_cost() {
        let (alone, helped) = (search(1), search(2));
        assert!(alone.2 > 4 * HINTED, "the search reaches enough nodes to hint: {}", alone.2);
        assert_eq!(helped.0, alone.0);
        assert_eq!(helped.1, alone.1);
        for node in 0..alone.3.node_count() {
            assert_eq!(helped.3.row_costs(0, node), alone.3.row_costs(0, node), "row {node}");
        }
    }
}
