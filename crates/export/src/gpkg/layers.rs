//! The GeoPackage's layers, built from the run: every geometry in world coordinates (the
//! artifacts' local ones plus the frame's origin), every id 1-based.
//!
//! - `segments`: one 3D line per skeleton segment, drawn in the direction water flows
//!   (conduit order when dry), with its conduit, type, zone, radius, flow, water type, phase.
//! - `conduits`: one 3D line per conduit, its length and main type (the type of most of its
//!   length).
//! - `passages`: each conduit's footprint on the map, one polygon per segment (the hull of the
//!   discs at its ends, [`crate::footprint`]) gathered in one multipolygon per conduit.
//! - `key_points`: the scene's key points as 3D points, named, with their kind and network
//!   node; a point read without z carries the terrain elevation the run used.
//! - `streams`: the surface streams, one 3D line per stream segment, with its water type
//!   (Table 1 of the streams stage), flow and fall.
//! - `routes`: the path of every sink to its spring through the network.

use karst_scene::{KeyPoint, KeyPointKind};
use karst_skeleton::{ConduitType, Skeleton};
use karst_streams::Streams;

use super::geometry::Geometry;
use super::style;
use crate::footprint::SegmentFootprint;
use crate::frame::Frame;
use crate::network::NetworkView;
use crate::surface::motion_name;

/// Sides of the discs whose hull draws a passage.
const DISC_SIDES: usize = 16;

/// An attribute value.
#[derive(Debug, Clone, PartialEq)]
pub enum Value {
    Integer(i64),
    /// NaN is written as NULL.
    Real(f64),
    Text(String),
    Null,
}

impl Value {
    pub(super) fn to_sql(&self) -> rusqlite::types::Value {
        use rusqlite::types::Value as Sql;
        match self {
            Value::Integer(i) => Sql::Integer(*i),
            Value::Real(r) if r.is_finite() => Sql::Real(*r),
            Value::Real(_) | Value::Null => Sql::Null,
            Value::Text(t) => Sql::Text(t.clone()),
        }
    }
}

fn text(s: &str) -> Value {
    Value::Text(s.to_string())
}

/// One feature: its geometry and its values, in the layer's column order.
#[derive(Debug, Clone, PartialEq)]
pub struct Feature {
    pub geometry: Geometry,
    pub values: Vec<Value>,
}

/// One feature table.
#[derive(Debug, Clone, PartialEq)]
pub struct Layer {
    pub name: &'static str,
    pub description: &'static str,
    /// `gpkg_geometry_columns.geometry_type_name`.
    pub geometry_type: &'static str,
    pub has_z: bool,
    /// Attribute columns: name and SQL type.
    pub columns: Vec<(&'static str, &'static str)>,
    pub features: Vec<Feature>,
    /// The default QGIS style (QML).
    pub style: String,
}

impl Layer {
    fn new(
        name: &'static str,
        description: &'static str,
        geometry: Geometry,
        columns: &[(&'static str, &'static str)],
        style: String,
    ) -> Layer {
        Layer {
            name,
            description,
            geometry_type: geometry.type_name(),
            has_z: geometry.has_z(),
            columns: columns.to_vec(),
            features: Vec::new(),
            style,
        }
    }

    fn push(&mut self, geometry: Geometry, values: Vec<Value>) {
        debug_assert_eq!(values.len(), self.columns.len());
        self.features.push(Feature { geometry, values });
    }
}

/// What the layers are made of.
pub struct Sources<'a> {
    pub frame: &'a Frame,
    pub net: &'a NetworkView,
    pub skeleton: &'a Skeleton,
    pub streams: &'a Streams,
    /// The scene's key points (local coordinates); empty when the scene is unknown.
    pub keypoints: &'a [KeyPoint],
}

/// Every layer, in the order they are written.
pub fn all(s: &Sources) -> Vec<Layer> {
    vec![segments(s), conduits(s), passages(s), key_points(s), streams(s), routes(s)]
}

fn line(frame: &Frame, points: impl IntoIterator<Item = [f64; 3]>) -> Geometry {
    Geometry::LineStringZ(points.into_iter().map(|p| frame.world(p)).collect())
}

fn segments(s: &Sources) -> Layer {
    let columns = [
        ("conduit", "INTEGER"),
        ("type", "TEXT"),
        ("zone", "TEXT"),
        ("radius", "REAL"),
        ("flow", "REAL"),
        ("discharge", "REAL"),
        ("water", "TEXT"),
        ("phase", "INTEGER"),
        ("length", "REAL"),
        ("strahler", "INTEGER"),
    ];
    let mut layer = Layer::new(
        "segments",
        "skeleton segments in the direction water flows; radius: mean of the ends, m; flow: network units; discharge: m3/s",
        Geometry::LineStringZ(Vec::new()),
        &columns,
        style::by_conduit_type(style::Shape::Line),
    );
    for seg in &s.net.segments {
        let ends = seg.flow_ends().map(|n| s.net.nodes[n as usize].position);
        layer.push(
            line(s.frame, ends),
            vec![
                Value::Integer(seg.conduit.into()),
                text(seg.conduit_type.name()),
                text(seg.zone.name()),
                Value::Real((seg.radius[0] + seg.radius[1]) / 2.0),
                Value::Real(seg.flow),
                Value::Real(seg.discharge),
                text(seg.water.name()),
                Value::Integer(seg.phase.into()),
                Value::Real(seg.length),
                Value::Integer(seg.strahler.into()),
            ],
        );
    }
    layer
}

/// The type of most of a conduit's length (the first of the tied ones in type order).
fn main_type(net: &NetworkView, range: std::ops::Range<usize>) -> ConduitType {
    let mut lengths = [0.0f64; ConduitType::ALL.len()];
    for seg in &net.segments[range] {
        lengths[crate::network::code(&ConduitType::ALL, seg.conduit_type) as usize] += seg.length;
    }
    let best = (0..lengths.len()).fold(0, |best, i| if lengths[i] > lengths[best] { i } else { best });
    ConduitType::ALL[best]
}

fn conduits(s: &Sources) -> Layer {
    let columns = [
        ("type", "TEXT"),
        ("length", "REAL"),
        ("segments", "INTEGER"),
        ("flow", "REAL"),
        ("phase", "INTEGER"),
    ];
    let mut layer = Layer::new(
        "conduits",
        "conduits in conduit order; type: the type of most of the length; length: m; flow: largest, network units",
        Geometry::LineStringZ(Vec::new()),
        &columns,
        style::by_conduit_type(style::Shape::Line),
    );
    for range in &s.net.conduits {
        let segs = &s.net.segments[range.clone()];
        let Some(first) = segs.first() else { continue };
        let nodes = std::iter::once(first.nodes[0]).chain(segs.iter().map(|g| g.nodes[1]));
        layer.push(
            line(s.frame, nodes.map(|n| s.net.nodes[n as usize].position)),
            vec![
                text(main_type(s.net, range.clone()).name()),
                Value::Real(segs.iter().map(|g| g.length).sum()),
                Value::Integer(segs.len() as i64),
                Value::Real(segs.iter().map(|g| g.flow).fold(0.0, f64::max)),
                Value::Integer(first.phase.into()),
            ],
        );
    }
    layer
}

fn passages(s: &Sources) -> Layer {
    let columns = [("conduit", "INTEGER"), ("type", "TEXT")];
    let mut layer = Layer::new(
        "passages",
        "conduit footprints on the map: the hull of the passage discs of each segment",
        Geometry::MultiPolygon(Vec::new()),
        &columns,
        style::by_conduit_type(style::Shape::Fill),
    );
    let footprints = SegmentFootprint::all(s.net);
    let origin = s.frame.origin();
    for (c, range) in s.net.conduits.iter().enumerate() {
        if range.is_empty() {
            continue;
        }
        let rings = footprints[range.clone()]
            .iter()
            .map(|f| f.outline(DISC_SIDES).into_iter().map(|[x, y]| [x + origin[0], y + origin[1]]).collect())
            .collect();
        layer.push(
            Geometry::MultiPolygon(rings),
            vec![Value::Integer(c as i64 + 1), text(main_type(s.net, range.clone()).name())],
        );
    }
    layer
}

/// A key point kind's name, as in the scene.
fn kind_name(kind: KeyPointKind) -> &'static str {
    match kind {
        KeyPointKind::Sink => "sink",
        KeyPointKind::Spring => "spring",
        KeyPointKind::Waypoint => "waypoint",
        KeyPointKind::DeadEnd => "dead_end",
    }
}

fn key_points(s: &Sources) -> Layer {
    let columns = [("name", "TEXT"), ("kind", "TEXT"), ("node", "INTEGER"), ("weight", "REAL")];
    let mut layer = Layer::new(
        "key_points",
        "the scene's key points; z: as given, or the terrain elevation where the input had none; node: 1-based network node",
        Geometry::PointZ([0.0; 3]),
        &columns,
        style::key_points(),
    );
    for k in s.keypoints {
        let node = s.net.nodes.iter().position(|n| n.keypoint.as_deref() == Some(&k.name));
        layer.push(
            Geometry::PointZ(s.frame.world(k.position)),
            vec![
                text(&k.name),
                text(kind_name(k.kind)),
                node.map_or(Value::Null, |n| Value::Integer(n as i64 + 1)),
                Value::Real(k.weight),
            ],
        );
    }
    layer
}

fn streams(s: &Sources) -> Layer {
    let columns = [
        ("water", "TEXT"),
        ("motion", "TEXT"),
        ("flow", "REAL"),
        ("slope", "REAL"),
        ("width", "REAL"),
        ("fall_drop", "REAL"),
        ("fall_throw", "REAL"),
    ];
    let mut layer = Layer::new(
        "streams",
        "surface streams, downstream; water: Table 1 water type; flow: m3/s; fall_drop, fall_throw: m, empty without a fall",
        Geometry::LineStringZ(Vec::new()),
        &columns,
        style::streams(),
    );
    let streams = s.streams;
    for seg in &streams.segments {
        let ends = [seg.from, seg.to].map(|n| streams.nodes[n as usize].position);
        let fall = seg.fall.as_ref();
        layer.push(
            line(s.frame, ends),
            vec![
                text(seg.water.name()),
                text(motion_name(seg.motion)),
                Value::Real(seg.flow),
                Value::Real(seg.slope),
                Value::Real(seg.width),
                fall.map_or(Value::Null, |f| Value::Real(f.drop)),
                fall.map_or(Value::Null, |f| Value::Real(f.throw)),
            ],
        );
    }
    layer
}

fn routes(s: &Sources) -> Layer {
    let columns =
        [("sink", "TEXT"), ("spring", "TEXT"), ("weight", "REAL"), ("cost", "REAL"), ("length", "REAL")];
    let mut layer = Layer::new(
        "routes",
        "the path of each sink's water to its spring; length: m",
        Geometry::LineStringZ(Vec::new()),
        &columns,
        style::routes(),
    );
    for route in s.skeleton.routes.iter().filter(|r| r.nodes.len() >= 2) {
        let points: Vec<[f64; 3]> =
            route.nodes.iter().map(|&n| s.skeleton.nodes[n as usize].position).collect();
        let length: f64 =
            points.windows(2).map(|w| (0..3).map(|a| (w[1][a] - w[0][a]).powi(2)).sum::<f64>().sqrt()).sum();
        layer.push(
            line(s.frame, points),
            vec![
                text(&route.sink),
                text(&route.spring),
                Value::Real(route.weight),
                Value::Real(route.cost),
                Value::Real(length),
            ],
        );
    }
    layer
}
