//! The cost graph's work estimate, made before the neighbours are searched: k edges per sample
//! (twice as many when symmetrised), each with its target (held twice while the rows are
//! symmetrised, which reassembles them) and one f32 cost per cost set, plus per-sample fields (position,
//! potential, one distance per surface and per water table) and the search grid. The costs are
//! counted as if every row were stored apart in every later set (the upper bound: which rows
//! share set 0's costs is known only once they are costed).

use karst_scene::budget::{Cheaper, Estimate, OverBudget};

use crate::view::CostgraphView;

/// Bytes per edge and per cost set at the peak: its f32 cost, written in place.
const BYTES_PER_EDGE_AND_SET: f64 = 4.0;
/// Bytes per edge besides its costs: its target (twice while symmetrising), the stats' share.
const BYTES_PER_EDGE: f64 = 12.0;
/// Bytes per sample besides its fields: the grid's copy of the points, the order, offsets.
const BYTES_PER_SAMPLE: f64 = 64.0;

/// Refuses a cost graph of `samples` samples that would not fit in the memory budget.
pub fn check(view: &CostgraphView, samples: usize, sets: usize) -> Result<(), OverBudget> {
    let p = view.costgraph;
    let g = view.geology;
    let fields = 4 + g.horizons.len() + g.faults.len() + sets;
    let n = samples as f64;
    let bytes = |k: f64| {
        let edges = n * k * if p.symmetrise { 2.0 } else { 1.0 };
        n * (BYTES_PER_SAMPLE + 8.0 * fields as f64)
            + edges * (BYTES_PER_EDGE + BYTES_PER_EDGE_AND_SET * sets as f64)
    };
    let k = p.k as f64;
    let estimate = Estimate {
        what: format!("{:.2e} edges for {samples} samples", n * k),
        bytes: bytes(k),
        field: "costgraph.k".into(),
        value: k,
    };
    view.budget.check(estimate, Cheaper::Smaller, true, bytes)
}
