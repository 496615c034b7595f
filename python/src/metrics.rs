//! karstnet's statistics of any network from Python: `karstgen.metrics(nodes, edges)` (and of
//! a karstnet `KGraph`, whose nodes and edges the Python side extracts), identical to
//! karstnet 1.2.5's `characterize_graph` (docs/metrics.md).

use pyo3::prelude::*;

use karst_metrics::{Network, characterize as characterize_network};

use crate::errors::argument;

/// Every statistic `(name, value)` under karstnet's key names, of the network whose node
/// coordinates are `nodes` (float64, N × 3, as bytes) and links `links` (int64, M × 2, 0-based
/// node indices, as bytes).
#[pyfunction]
pub fn characterize(py: Python<'_>, nodes: &[u8], links: &[u8]) -> PyResult<Vec<(String, f64)>> {
    if !nodes.len().is_multiple_of(24) || !links.len().is_multiple_of(16) {
        return Err(argument("nodes must be N × 3 float64 and edges M × 2 integers"));
    }
    let word = |b: &[u8]| <[u8; 8]>::try_from(b).unwrap_or_default();
    let coordinates: Vec<f64> = nodes.chunks_exact(8).map(|b| f64::from_le_bytes(word(b))).collect();
    let ends: Vec<i64> = links.chunks_exact(8).map(|b| i64::from_le_bytes(word(b))).collect();
    let links = ends
        .chunks_exact(2)
        .enumerate()
        .map(|(i, pair)| match (usize::try_from(pair[0]), usize::try_from(pair[1])) {
            (Ok(a), Ok(b)) => Ok([a, b]),
            _ => Err(argument(format!("edge {i} ({}, {}) has a negative node index", pair[0], pair[1]))),
        })
        .collect::<PyResult<Vec<_>>>()?;
    let network = Network { nodes: coordinates.chunks_exact(3).map(|c| [c[0], c[1], c[2]]).collect(), links };
    let metrics =
        py.detach(|| characterize_network(&network)).map_err(|e| argument(format!("the network: {e}")))?;
    Ok(metrics.to_pairs().into_iter().map(|(k, v)| (k.to_string(), v)).collect())
}
