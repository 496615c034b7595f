//! The cost graph stage's contract: its view of the scene and `samples.bin` in, `costgraph.bin`
//! out.

use karst_artifact::{Header, StageId};
use karst_sampling::Samples;
use karst_stage::Stage;

use crate::build::build;
use crate::error::CostGraphError;
use crate::payload::CostGraph;
use crate::view::CostgraphView;

/// Stage 2: the k-nearest-neighbour graph of the samples and its edge costs.
pub struct CostgraphStage;

impl Stage for CostgraphStage {
    const ID: StageId = StageId::Costgraph;
    type Inputs = (Samples,);
    type Output = CostGraph;
    type Error = CostGraphError;
    type View<'s> = CostgraphView<'s>;

    fn build(view: &CostgraphView, (samples,): &(Samples,)) -> Result<CostGraph, CostGraphError> {
        build(view, samples)
    }

    fn headline(_: &CostgraphView, graph: &CostGraph) -> String {
        format!(
            "{} nodes, {} edges, {} cost set(s)",
            graph.node_count(),
            graph.edge_count(),
            graph.cost_sets.len()
        )
    }

    /// Counts, memory, and the distribution of edge lengths and of every cost term in every
    /// cost set.
    fn summary(header: &Header, graph: &CostGraph) -> Vec<String> {
        let edges = graph.edge_count().max(1) as f64;
        let mut lines = Vec::new();
        lines.push(format!("model     {}", graph.summary.model));
        lines.push(format!("nodes     {}", graph.node_count()));
        lines.push(format!(
            "edges     {} ({:.1} per node)",
            graph.edge_count(),
            edges / graph.node_count().max(1) as f64
        ));
        lines.push(format!(
            "memory    {} bytes ({:.1} per edge); file payload {} bytes ({:.1} per edge)",
            graph.bytes_in_memory(),
            graph.bytes_in_memory() as f64 / edges,
            header.payload_len,
            header.payload_len as f64 / edges
        ));
        if graph.cost_sets.len() > 1 {
            lines.push(format!(
                "own rows  {:.1} % (rows that may differ between cost sets, stored in each; the others in set 0 only)",
                100.0 * graph.own_row_share()
            ));
        }
        if let Some(lengths) = &graph.summary.lengths {
            lines.push(format!("length m  {}", lengths.line()));
        }
        for set in &graph.summary.sets {
            match &set.water_table {
                Some(w) => lines.push(format!("cost set of water table \"{w}\"")),
                None => lines.push("cost set".to_string()),
            }
            for term in &set.terms {
                lines.push(format!("  {:<17} × {:<6} {}", term.name, term.weight, term.histogram.line()));
            }
            lines.push(format!("  {:<26} {}", "cost per metre", set.cost_per_metre.line()));
        }
        lines
    }
}
