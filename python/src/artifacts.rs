//! A run's artifacts for Python, read and checked as every stage reads them (format, kind,
//! schema, length, checksum, consistency): the network as columns, the meshes, any JSON
//! payload, and the figures an ensemble tables.
//!
//! Numeric columns cross as `bytes` (little-endian on every machine karstgen targets) with a
//! NumPy dtype code (`f8`, `i8`, `u4`, `?`); text columns as lists.

use std::path::{Path, PathBuf};

use pyo3::prelude::*;
use pyo3::types::{PyBytes, PyDict, PyList};

use karst_artifact::{StageId, read_artifact, read_header};
use karst_hydro::Hydro;
use karst_mesher::Mesh;
use karst_pipeline::ensemble::realization::network_figures;
use karst_pipeline::ensemble::{Figures, table};
use karst_pipeline::registry;
use karst_skeleton::Skeleton;
use karst_stage::StageError;

use crate::errors::to_py;

/// One column of a table.
enum Column {
    F64(Vec<f64>),
    I64(Vec<i64>),
    U32(Vec<u32>),
    Bool(Vec<bool>),
    Text(Vec<Option<String>>),
}

impl Column {
    fn into_py<'py>(self, py: Python<'py>) -> PyResult<(&'static str, Bound<'py, PyAny>)> {
        let bytes = |b: Vec<u8>| PyBytes::new(py, &b).into_any();
        Ok(match self {
            Column::F64(v) => ("f8", bytes(v.iter().flat_map(|x| x.to_le_bytes()).collect())),
            Column::I64(v) => ("i8", bytes(v.iter().flat_map(|x| x.to_le_bytes()).collect())),
            Column::U32(v) => ("u4", bytes(v.iter().flat_map(|x| x.to_le_bytes()).collect())),
            Column::Bool(v) => ("?", bytes(v.iter().map(|&x| u8::from(x)).collect())),
            Column::Text(v) => ("str", PyList::new(py, v)?.into_any()),
        })
    }
}

type Table = Vec<(&'static str, Column)>;

/// The network of a run: node coordinates, edges, and the node, edge (segment) and conduit
/// tables, with the water of each when `hydro.json` is there and made from this skeleton.
struct NetworkTables {
    nodes: Vec<f64>,
    edges: Vec<i64>,
    node_table: Table,
    edge_table: Table,
    conduit_table: Table,
}

/// `{"nodes": bytes, "edges": bytes, "node_columns": [...], "edge_columns": [...],
/// "conduit_columns": [...]}` of the run in `out`; columns are `(name, dtype, data)`.
#[pyfunction]
pub fn read_network<'py>(py: Python<'py>, out: PathBuf) -> PyResult<Bound<'py, PyDict>> {
    let tables = py.detach(|| network(&out)).map_err(to_py)?;
    let dict = PyDict::new(py);
    dict.set_item("nodes", PyBytes::new(py, &le_bytes(&tables.nodes)))?;
    dict.set_item(
        "edges",
        PyBytes::new(py, &tables.edges.iter().flat_map(|x| x.to_le_bytes()).collect::<Vec<u8>>()),
    )?;
    for (key, table) in [
        ("node_columns", tables.node_table),
        ("edge_columns", tables.edge_table),
        ("conduit_columns", tables.conduit_table),
    ] {
        let columns = PyList::empty(py);
        for (name, column) in table {
            let (dtype, data) = column.into_py(py)?;
            columns.append((name, dtype, data))?;
        }
        dict.set_item(key, columns)?;
    }
    Ok(dict)
}

fn le_bytes(values: &[f64]) -> Vec<u8> {
    values.iter().flat_map(|x| x.to_le_bytes()).collect()
}

fn network(out: &Path) -> Result<NetworkTables, StageError> {
    let skeleton_path = out.join(StageId::Skeleton.file_name());
    let (header, skeleton) = read_artifact::<Skeleton>(&skeleton_path)?;
    let hydro = current_hydro(out, &header.payload_blake3)?;
    if let Some(h) = &hydro {
        karst_metrics::water_type_lengths(&skeleton, h).map_err(|e| {
            StageError::artifact(format!("{}: {e}", out.join(StageId::Hydro.file_name()).display()))
        })?;
    }
    Ok(NetworkTables {
        nodes: skeleton.nodes.iter().flat_map(|n| n.position).collect(),
        edges: skeleton.links().iter().flat_map(|l| l.map(i64::from)).collect(),
        node_table: node_table(&skeleton, hydro.as_ref()),
        edge_table: edge_table(&skeleton, hydro.as_ref()),
        conduit_table: conduit_table(&skeleton, hydro.as_ref()),
    })
}

/// `hydro.json` of `out` when it was made from the skeleton whose payload hash is `skeleton`.
fn current_hydro(out: &Path, skeleton: &str) -> Result<Option<Hydro>, StageError> {
    let path = out.join(StageId::Hydro.file_name());
    let Ok(header) = read_header(&path) else { return Ok(None) };
    if !header.inputs.iter().any(|i| i.payload_blake3 == skeleton) {
        return Ok(None);
    }
    Ok(Some(read_artifact::<Hydro>(&path)?.1))
}

fn node_table(skeleton: &Skeleton, hydro: Option<&Hydro>) -> Table {
    let nodes = &skeleton.nodes;
    let mut table = vec![
        ("x", Column::F64(nodes.iter().map(|n| n.position[0]).collect())),
        ("y", Column::F64(nodes.iter().map(|n| n.position[1]).collect())),
        ("z", Column::F64(nodes.iter().map(|n| n.position[2]).collect())),
        ("zone", Column::Text(nodes.iter().map(|n| Some(name_of(&n.zone))).collect())),
        ("keypoint", Column::Text(nodes.iter().map(|n| n.keypoint.clone()).collect())),
        ("sample", Column::U32(nodes.iter().map(|n| n.sample).collect())),
    ];
    if let Some(h) = hydro {
        table.push(("role", Column::Text(h.nodes.iter().map(|n| Some(name_of(&n.role))).collect())));
        table.push(("inflow", Column::F64(h.nodes.iter().map(|n| n.inflow).collect())));
    }
    table
}

/// One row per segment, in the order of `edges` (conduit by conduit); `source < target`.
fn edge_table(skeleton: &Skeleton, hydro: Option<&Hydro>) -> Table {
    let mut source = Vec::new();
    let mut target = Vec::new();
    let mut conduit = Vec::new();
    let mut kind = Vec::new();
    let mut radius = (Vec::new(), Vec::new());
    let mut phase = Vec::new();
    let mut reversed = Vec::new();
    for (c, k) in skeleton.conduits.iter().enumerate() {
        for (i, w) in k.nodes.windows(2).enumerate() {
            let flipped = w[0] > w[1];
            let (s, t) = if flipped { (i + 1, i) } else { (i, i + 1) };
            source.push(i64::from(k.nodes[s]));
            target.push(i64::from(k.nodes[t]));
            conduit.push(c as i64);
            kind.push(Some(name_of(&k.types[i])));
            radius.0.push(k.radius[s]);
            radius.1.push(k.radius[t]);
            phase.push(i64::from(k.phase));
            reversed.push(flipped);
        }
    }
    let mut table = vec![
        ("source", Column::I64(source)),
        ("target", Column::I64(target)),
        ("conduit", Column::I64(conduit)),
        ("type", Column::Text(kind)),
        ("radius_source", Column::F64(radius.0)),
        ("radius_target", Column::F64(radius.1)),
        ("phase", Column::I64(phase)),
    ];
    if let Some(h) = hydro {
        let segments: Vec<_> = h.conduits.iter().flat_map(|c| &c.segments).collect();
        let f = |get: fn(&karst_hydro::SegmentWater) -> f64| {
            Column::F64(segments.iter().map(|s| get(s)).collect())
        };
        table.extend([
            ("flow", f(|s| s.flow)),
            ("discharge", f(|s| s.discharge)),
            ("water_type", Column::Text(segments.iter().map(|s| Some(s.water.name().to_string())).collect())),
            (
                "towards_target",
                Column::Bool(
                    segments.iter().zip(&reversed).map(|(s, &r)| s.flow > 0.0 && s.downstream != r).collect(),
                ),
            ),
            ("speed", f(|s| s.speed)),
            ("depth", f(|s| s.depth)),
            ("width", f(|s| s.width)),
            ("slope", f(|s| s.slope)),
        ]);
    }
    table
}

fn conduit_table(skeleton: &Skeleton, hydro: Option<&Hydro>) -> Table {
    let c = &skeleton.conduits;
    let mut table = vec![
        ("first_node", Column::I64(c.iter().map(|k| i64::from(k.nodes[0])).collect())),
        ("last_node", Column::I64(c.iter().map(|k| i64::from(k.nodes[k.nodes.len() - 1])).collect())),
        ("segments", Column::I64(c.iter().map(|k| k.nodes.len() as i64 - 1).collect())),
        ("length", Column::F64(c.iter().map(|k| skeleton.conduit_length(k)).collect())),
        ("phase", Column::I64(c.iter().map(|k| i64::from(k.phase)).collect())),
        ("keypoints", Column::Text(c.iter().map(|k| Some(k.keypoints.join(","))).collect())),
    ];
    if let Some(h) = hydro {
        table.push(("flow", Column::F64(h.conduits.iter().map(|w| w.flow).collect())));
        table.push(("dry", Column::Bool(h.conduits.iter().map(|w| w.dry).collect())));
    }
    table
}

/// The snake-case name serde gives a unit variant.
fn name_of(value: &impl serde::Serialize) -> String {
    serde_json::to_value(value).ok().and_then(|v| v.as_str().map(str::to_string)).unwrap_or_default()
}

/// `(vertices, triangles, vertex count, triangle count)` of one surface (`terrain`, `cave`,
/// `water`) of a mesh artifact: float32 (V, 3) and uint32 (F, 3) as bytes.
#[pyfunction]
pub fn read_mesh<'py>(
    py: Python<'py>,
    path: PathBuf,
    surface: String,
) -> PyResult<(Bound<'py, PyBytes>, Bound<'py, PyBytes>, usize, usize)> {
    let (vertices, triangles, nv, nf) = py
        .detach(|| {
            let (_, mesh) = read_artifact::<Mesh>(&path)?;
            let Some((_, m)) = mesh.surfaces().into_iter().find(|(name, _)| *name == surface) else {
                return Err(StageError::input(format!(
                    "no surface \"{surface}\" in a mesh: terrain, cave or water"
                )));
            };
            let v: Vec<u8> = m.vertices.iter().flatten().flat_map(|x| x.to_le_bytes()).collect();
            let f: Vec<u8> = m.triangles.iter().flatten().flat_map(|x| x.to_le_bytes()).collect();
            Ok((v, f, m.vertices.len(), m.triangles.len()))
        })
        .map_err(to_py)?;
    Ok((PyBytes::new(py, &vertices), PyBytes::new(py, &triangles), nv, nf))
}

/// The payload of any artifact, checked, as JSON text.
#[pyfunction]
pub fn read_payload(py: Python<'_>, path: PathBuf) -> PyResult<String> {
    py.detach(|| {
        let header = read_header(&path)?;
        Ok(registry::stage(header.kind).payload_value(&path)?.to_string())
    })
    .map_err(to_py)
}

/// `(columns, values)`: the figures of the run in `out` as an ensemble tables them (every
/// metric, lengths per zone, conduit type and, when hydro ran on this skeleton, water type;
/// spring discharges), `seed` first.
#[pyfunction]
pub fn figures(py: Python<'_>, out: PathBuf, seed: u64) -> PyResult<(Vec<String>, Vec<f64>)> {
    py.detach(|| {
        let header = read_header(&out.join(StageId::Skeleton.file_name()))?;
        let hydro = current_hydro(&out, &header.payload_blake3)?.is_some();
        let (report, springs, _) = network_figures(&out, hydro)?;
        let figures = Figures { report, springs, cells: Vec::new(), columns: Default::default() };
        let t = table::table(&[(seed, &figures)]);
        Ok((t.columns, t.rows.into_iter().next().unwrap_or_default()))
    })
    .map_err(to_py)
}
