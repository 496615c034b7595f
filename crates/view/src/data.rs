//! `view/data/run.json`: everything the page shows that is not a mesh, gathered from the run's
//! artifacts and its scene — the network (skeleton nodes and conduits), the water on every
//! segment (hydro), the surface streams as polylines with their Table 1 types, the routes
//! from sink to spring, the key points, the water tables and
//! horizons sampled on a grid, karstnet's metrics, the ensemble probability of every segment, the mesh chunks to load, and the
//! [`Problem`]s that leave a layer empty.
//!
//! The skeleton and the metrics report go in as their artifacts define them (docs/skeleton.md,
//! docs/metrics.md); the hydro artifact is reduced to what the viewer colours and prints, as
//! one array per field and conduit, which keeps the file small for the largest presets.

use serde::Serialize;

use karst_geology::Surface;
use karst_hydro::{Hydro, Role, WaterType};
use karst_metrics::MetricsReport;
use karst_scene::{KeyPointKind, Scene};
use karst_skeleton::Skeleton;
use karst_streams::{Motion, Streams};

use crate::ensemble::EnsembleView;
use crate::meshes::MeshView;
use crate::run::{Problem, Run};

/// The value of `format` in run.json.
pub const FORMAT: &str = "karstgen-view";
/// Bumped on every change of run.json's layout (the app checks it).
pub const VERSION: u32 = 2;
/// Grid points per side of a sampled water table or horizon.
const SURFACE_GRID: usize = 48;
/// Points along each free fall's parabola in a streams polyline.
const FALL_POINTS: usize = 12;

/// The document.
#[derive(Serialize)]
pub struct ViewData<'a> {
    pub format: &'static str,
    pub version: u32,
    /// The run folder's name.
    pub run: String,
    pub problems: &'a [Problem],
    /// The scene's domain, or the bounds of what the run holds.
    pub domain: Option<Bounds>,
    pub skeleton: Option<&'a Skeleton>,
    pub hydro: Option<HydroView>,
    pub streams: Option<StreamsView>,
    pub keypoints: Vec<KeyPointView>,
    pub surfaces: Vec<SurfaceView>,
    pub meshes: &'a [MeshView],
    pub metrics: Option<&'a MetricsReport>,
    /// The ensemble probability of every segment, when the run holds an ensemble.
    pub ensemble: Option<&'a EnsembleView>,
}

/// An axis-aligned box, metres.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Bounds {
    pub min: [f64; 3],
    pub max: [f64; 3],
}

impl Bounds {
    fn of(points: impl Iterator<Item = [f64; 3]>) -> Option<Bounds> {
        points.fold(None, |b: Option<Bounds>, p| {
            let b = b.unwrap_or(Bounds { min: p, max: p });
            Some(Bounds {
                min: [0, 1, 2].map(|a| b.min[a].min(p[a])),
                max: [0, 1, 2].map(|a| b.max[a].max(p[a])),
            })
        })
    }
}

/// The water of the network, one entry per skeleton conduit and node.
#[derive(Serialize)]
pub struct HydroView {
    pub conduits: Vec<ConduitWaterView>,
    pub nodes: Vec<NodeWaterView>,
    pub springs: Vec<FlowAtPoint>,
    pub sinks: Vec<FlowAtPoint>,
}

/// One conduit's water: per segment `nodes[i] → nodes[i + 1]`, one value in each array.
#[derive(Serialize)]
pub struct ConduitWaterView {
    pub dry: bool,
    /// Largest flow of its segments, network units.
    pub flow: f64,
    /// Radii sized from the flow, when hydro sized them.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub radius: Option<Vec<f64>>,
    pub downstream: Vec<bool>,
    pub segment_flow: Vec<f64>,
    /// m³/s.
    pub discharge: Vec<f64>,
    pub water: Vec<WaterType>,
    /// Water depth above the floor, metres.
    pub depth: Vec<f64>,
}

/// The surface streams (streams.json), one entry per segment.
#[derive(Serialize)]
pub struct StreamsView {
    pub segments: Vec<StreamSegmentView>,
}

/// A surface segment as the page draws it.
#[derive(Serialize)]
pub struct StreamSegmentView {
    /// Table 1 type (pool: across a pool).
    pub water: WaterType,
    pub motion: Motion,
    /// m³/s.
    pub flow: f64,
    /// Its course: the two ends, or points along a fall's parabola from the lip to the impact.
    pub points: Vec<[f64; 3]>,
}

/// The role of a node in the hydraulic graph and the water arriving there.
#[derive(Serialize)]
pub struct NodeWaterView {
    pub role: Role,
    pub inflow: f64,
}

/// A sink's recharge or a spring's discharge (network units).
#[derive(Serialize)]
pub struct FlowAtPoint {
    pub name: String,
    pub node: u32,
    pub flow: f64,
}

/// A key point: from the scene when there is one, else the named nodes of the skeleton.
#[derive(Serialize)]
pub struct KeyPointView {
    pub name: String,
    /// sink, spring, waypoint, dead_end, or key point (kind unknown without the scene).
    pub kind: String,
    pub position: [f64; 3],
    /// The skeleton node at the key point.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub node: Option<u32>,
}

/// A water table or horizon, its elevation on a regular grid over the domain (row-major, x
/// fastest).
#[derive(Serialize)]
pub struct SurfaceView {
    pub name: String,
    /// "water table" or "horizon".
    pub kind: &'static str,
    pub nx: usize,
    pub ny: usize,
    pub min: [f64; 2],
    pub max: [f64; 2],
    pub z: Vec<f64>,
}

/// Gathers the document of `run` with its mesh manifest.
pub fn view_data<'a>(run: &'a Run, meshes: &'a [MeshView]) -> ViewData<'a> {
    ViewData {
        format: FORMAT,
        version: VERSION,
        run: run.name(),
        problems: &run.problems,
        domain: domain(run, meshes),
        skeleton: run.skeleton.as_ref(),
        hydro: run.hydro.as_ref().map(hydro_view),
        streams: run.streams.as_ref().map(streams_view),
        keypoints: keypoints(run),
        surfaces: run.scene.as_ref().map(surfaces).unwrap_or_default(),
        meshes,
        metrics: run.metrics.as_ref(),
        ensemble: run.ensemble.as_ref(),
    }
}

fn domain(run: &Run, meshes: &[MeshView]) -> Option<Bounds> {
    if let Some(scene) = &run.scene {
        return Some(Bounds { min: scene.domain().min, max: scene.domain().max });
    }
    let nodes = run.skeleton.iter().flat_map(|s| s.nodes.iter().map(|n| n.position));
    let chunks = meshes.iter().flat_map(|m| &m.chunks).flat_map(|c| [c.min, c.max]);
    Bounds::of(nodes.chain(chunks.map(|p| p.map(f64::from))))
}

fn hydro_view(hydro: &Hydro) -> HydroView {
    let conduits = hydro
        .conduits
        .iter()
        .map(|c| ConduitWaterView {
            dry: c.dry,
            flow: c.flow,
            radius: c.radius.clone(),
            downstream: c.segments.iter().map(|s| s.downstream).collect(),
            segment_flow: c.segments.iter().map(|s| s.flow).collect(),
            discharge: c.segments.iter().map(|s| s.discharge).collect(),
            water: c.segments.iter().map(|s| s.water).collect(),
            depth: c.segments.iter().map(|s| s.depth).collect(),
        })
        .collect();
    let at = |name: &str, node: u32, flow: f64| FlowAtPoint { name: name.into(), node, flow };
    HydroView {
        conduits,
        nodes: hydro.nodes.iter().map(|n| NodeWaterView { role: n.role, inflow: n.inflow }).collect(),
        springs: hydro.springs.iter().map(|s| at(&s.name, s.node, s.flow)).collect(),
        sinks: hydro.sinks.iter().map(|s| at(&s.name, s.node, s.recharge)).collect(),
    }
}

fn streams_view(streams: &Streams) -> StreamsView {
    let segments = streams
        .segments
        .iter()
        .map(|g| {
            let points = match &g.fall {
                Some(fall) => {
                    (0..=FALL_POINTS).map(|k| fall.at(fall.throw * k as f64 / FALL_POINTS as f64)).collect()
                }
                None => vec![streams.nodes[g.from as usize].position, streams.nodes[g.to as usize].position],
            };
            StreamSegmentView { water: g.water, motion: g.motion, flow: g.flow, points }
        })
        .collect();
    StreamsView { segments }
}

fn keypoints(run: &Run) -> Vec<KeyPointView> {
    let node_of = |name: &str| {
        run.skeleton
            .as_ref()
            .and_then(|s| s.nodes.iter().position(|n| n.keypoint.as_deref() == Some(name)).map(|i| i as u32))
    };
    if let Some(scene) = &run.scene {
        return scene
            .keypoints()
            .iter()
            .map(|k| KeyPointView {
                name: k.name.clone(),
                kind: kind_name(k.kind).into(),
                position: k.position,
                node: node_of(&k.name),
            })
            .collect();
    }
    let Some(skeleton) = &run.skeleton else { return Vec::new() };
    let kind_of = |name: &str| {
        let hydro = run.hydro.as_ref();
        if hydro.is_some_and(|h| h.sinks.iter().any(|s| s.name == name)) {
            "sink"
        } else if hydro.is_some_and(|h| h.springs.iter().any(|s| s.name == name)) {
            "spring"
        } else {
            "key point"
        }
    };
    skeleton
        .nodes
        .iter()
        .enumerate()
        .filter_map(|(i, n)| {
            let name = n.keypoint.as_ref()?;
            Some(KeyPointView {
                name: name.clone(),
                kind: kind_of(name).into(),
                position: n.position,
                node: Some(i as u32),
            })
        })
        .collect()
}

fn kind_name(kind: KeyPointKind) -> &'static str {
    match kind {
        KeyPointKind::Sink => "sink",
        KeyPointKind::Spring => "spring",
        KeyPointKind::Waypoint => "waypoint",
        KeyPointKind::DeadEnd => "dead_end",
    }
}

/// The water tables and horizons on a grid over the domain.
fn surfaces(scene: &Scene) -> Vec<SurfaceView> {
    let tables = scene.geology().water_tables.iter().map(|s| (s, "water table"));
    let horizons = scene.geology().horizons.iter().map(|s| (s, "horizon"));
    tables.chain(horizons).map(|(s, kind)| sample(scene, s, kind)).collect()
}

fn sample(scene: &Scene, surface: &Surface, kind: &'static str) -> SurfaceView {
    let (min, max) = (scene.domain().min, scene.domain().max);
    let n = SURFACE_GRID;
    let at = |a: usize, i: usize| min[a] + (max[a] - min[a]) * i as f64 / (n - 1) as f64;
    let z = (0..n)
        .flat_map(|j| (0..n).map(move |i| (i, j)))
        .map(|(i, j)| surface.elevation_at(at(0, i), at(1, j)));
    SurfaceView {
        name: surface.name.clone(),
        kind,
        nx: n,
        ny: n,
        min: [min[0], min[1]],
        max: [max[0], max[1]],
        z: z.collect(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn bounds_cover_every_point() {
        let b = Bounds::of([[1.0, 5.0, -2.0], [3.0, -1.0, 4.0]].into_iter()).unwrap();
        assert_eq!(b, Bounds { min: [1.0, -1.0, -2.0], max: [3.0, 5.0, 4.0] });
        assert_eq!(Bounds::of(std::iter::empty()), None);
    }
}
