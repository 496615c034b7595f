//! VTK XML PolyData (`.vtp`, ParaView, VTK 9): `network.vtp`, one line cell per conduit
//! segment with point and cell data, and `terrain.vtp` / `cave.vtp` / `water.vtp`, triangles
//! with normals; `streams.vtp`, one line cell per segment of the surface streams (a free fall
//! as the chord from its lip to its impact, its parabola's drop and throw as cell data). Points are Float64 world coordinates. The data is appended raw (little-endian,
//! each block prefixed by its UInt64 byte count) and streamed: the XML header's offsets are
//! computed from the counts before a byte of data is written. The origin is recorded as field
//! data (`origin`).

use std::io::{self, Write};

use karst_hydro::WaterType;
use karst_scene::params::ExportFormat;
use karst_skeleton::{ConduitType, Zone};
use karst_streams::{Segment, Streams};

use crate::ExportError;
use crate::folder::{Fill, Folder, Surfaces};
use crate::frame::Frame;
use crate::network::{NetworkView, NodeKind, SegmentZone, code};
use crate::surface::{MOTIONS, ROLES};

/// One data array: its VTK type, name, components, tuples and how to write its values.
struct Array<'a> {
    name: &'static str,
    kind: Kind,
    components: usize,
    tuples: usize,
    write: Fill<'a>,
}

#[derive(Clone, Copy)]
enum Kind {
    Float64,
    Float32,
    Int32,
}

impl Kind {
    fn name(self) -> &'static str {
        match self {
            Kind::Float64 => "Float64",
            Kind::Float32 => "Float32",
            Kind::Int32 => "Int32",
        }
    }

    fn size(self) -> usize {
        match self {
            Kind::Float64 => 8,
            Kind::Float32 | Kind::Int32 => 4,
        }
    }
}

impl<'a> Array<'a> {
    fn bytes(&self) -> u64 {
        (self.tuples * self.components * self.kind.size()) as u64
    }

    fn f64s(name: &'static str, values: Vec<f64>) -> Array<'a> {
        let tuples = values.len();
        let write = move |w: &mut dyn Write| values.iter().try_for_each(|v| w.write_all(&v.to_le_bytes()));
        Array { name, kind: Kind::Float64, components: 1, tuples, write: Box::new(write) }
    }

    fn i32s(name: &'static str, values: Vec<i32>) -> Array<'a> {
        let tuples = values.len();
        let write = move |w: &mut dyn Write| values.iter().try_for_each(|v| w.write_all(&v.to_le_bytes()));
        Array { name, kind: Kind::Int32, components: 1, tuples, write: Box::new(write) }
    }

    fn points(tuples: usize, point: impl Fn(usize) -> [f64; 3] + 'a) -> Array<'a> {
        let write = move |w: &mut dyn Write| {
            (0..tuples).try_for_each(|i| point(i).iter().try_for_each(|c| w.write_all(&c.to_le_bytes())))
        };
        Array { name: "Points", kind: Kind::Float64, components: 3, tuples, write: Box::new(write) }
    }

    /// Connectivity of `cells` cells of `size` points each, `index(cell, corner)`.
    fn connectivity(cells: usize, size: usize, index: impl Fn(usize, usize) -> u32 + 'a) -> Array<'a> {
        let write = move |w: &mut dyn Write| {
            (0..cells).try_for_each(|c| {
                (0..size).try_for_each(|k| w.write_all(&(index(c, k) as i32).to_le_bytes()))
            })
        };
        Array {
            name: "connectivity",
            kind: Kind::Int32,
            components: 1,
            tuples: cells * size,
            write: Box::new(write),
        }
    }

    fn offsets(cells: usize, size: usize) -> Array<'a> {
        let write = move |w: &mut dyn Write| {
            (1..=cells).try_for_each(|c| w.write_all(&((c * size) as i32).to_le_bytes()))
        };
        Array { name: "offsets", kind: Kind::Int32, components: 1, tuples: cells, write: Box::new(write) }
    }
}

/// A PolyData piece: points, cells of one kind (`Lines` or `Polys`) and data arrays.
struct Piece<'a> {
    points: Array<'a>,
    cell_section: &'static str,
    cells: usize,
    connectivity: Array<'a>,
    offsets: Array<'a>,
    point_data: Vec<Array<'a>>,
    cell_data: Vec<Array<'a>>,
    /// Name of the point-data array ParaView should take as normals.
    normals: Option<&'static str>,
}

impl Piece<'_> {
    fn write(&self, w: &mut dyn Write, frame: &Frame) -> io::Result<()> {
        let mut offset = 0u64;
        let mut declare = |a: &Array, w: &mut dyn Write| -> io::Result<()> {
            writeln!(
                w,
                "        <DataArray type=\"{}\" Name=\"{}\" NumberOfComponents=\"{}\" format=\"appended\" offset=\"{offset}\"/>",
                a.kind.name(),
                a.name,
                a.components
            )?;
            offset += 8 + a.bytes();
            Ok(())
        };
        writeln!(w, "<?xml version=\"1.0\"?>")?;
        writeln!(
            w,
            "<VTKFile type=\"PolyData\" version=\"1.0\" byte_order=\"LittleEndian\" header_type=\"UInt64\">"
        )?;
        writeln!(w, "  <PolyData>")?;
        let [x, y, z] = frame.origin();
        writeln!(w, "    <FieldData>")?;
        writeln!(
            w,
            "      <DataArray type=\"Float64\" Name=\"origin\" NumberOfTuples=\"1\" NumberOfComponents=\"3\" format=\"ascii\">{x:?} {y:?} {z:?}</DataArray>"
        )?;
        writeln!(w, "    </FieldData>")?;
        let (lines, polys) = if self.cell_section == "Lines" { (self.cells, 0) } else { (0, self.cells) };
        writeln!(
            w,
            "    <Piece NumberOfPoints=\"{}\" NumberOfVerts=\"0\" NumberOfLines=\"{lines}\" NumberOfStrips=\"0\" NumberOfPolys=\"{polys}\">",
            self.points.tuples
        )?;
        match self.normals {
            Some(n) => writeln!(w, "      <PointData Normals=\"{n}\">")?,
            None => writeln!(w, "      <PointData>")?,
        }
        for a in &self.point_data {
            declare(a, w)?;
        }
        writeln!(w, "      </PointData>\n      <CellData>")?;
        for a in &self.cell_data {
            declare(a, w)?;
        }
        writeln!(w, "      </CellData>\n      <Points>")?;
        declare(&self.points, w)?;
        writeln!(w, "      </Points>\n      <{}>", self.cell_section)?;
        declare(&self.connectivity, w)?;
        declare(&self.offsets, w)?;
        writeln!(w, "      </{}>\n    </Piece>\n  </PolyData>", self.cell_section)?;
        write!(w, "  <AppendedData encoding=\"raw\">\n   _")?;
        let arrays = self.point_data.iter().chain(&self.cell_data);
        let arrays = arrays.chain([&self.points, &self.connectivity, &self.offsets]);
        for a in arrays {
            w.write_all(&a.bytes().to_le_bytes())?;
            (a.write)(w)?;
        }
        writeln!(w, "\n  </AppendedData>\n</VTKFile>")
    }
}

/// `network.vtp`.
pub fn write_network(folder: &mut Folder, frame: &Frame, net: &NetworkView) -> Result<(), ExportError> {
    let nodes = &net.nodes;
    let segments = &net.segments;
    let node_f64 = |f: fn(&crate::network::NodeRecord) -> f64| nodes.iter().map(f).collect::<Vec<_>>();
    let seg_f64 = |f: fn(&crate::network::SegmentRecord) -> f64| segments.iter().map(f).collect::<Vec<_>>();
    let seg_i32 = |f: fn(&crate::network::SegmentRecord) -> i32| segments.iter().map(f).collect::<Vec<_>>();
    let piece = Piece {
        points: Array::points(nodes.len(), |i| frame.world(nodes[i].position)),
        cell_section: "Lines",
        cells: segments.len(),
        connectivity: Array::connectivity(segments.len(), 2, |c, k| segments[c].nodes[k]),
        offsets: Array::offsets(segments.len(), 2),
        point_data: vec![
            Array::i32s("node_id", (1..=nodes.len() as i32).collect()),
            Array::f64s("elevation", nodes.iter().map(|n| frame.world(n.position)[2]).collect()),
            Array::f64s("radius", node_f64(|n| n.radius)),
            Array::i32s("node_kind", nodes.iter().map(|n| code(&NodeKind::ALL, n.kind)).collect()),
            Array::i32s(
                "node_zone",
                nodes.iter().map(|n| code(&[Zone::Vadose, Zone::Phreatic], n.zone)).collect(),
            ),
            Array::i32s("degree", nodes.iter().map(|n| n.degree as i32).collect()),
        ],
        cell_data: vec![
            Array::i32s("segment_id", seg_i32(|s| s.id as i32)),
            Array::i32s("conduit_id", seg_i32(|s| s.conduit as i32)),
            Array::i32s("conduit_type", seg_i32(|s| code(&ConduitType::ALL, s.conduit_type))),
            Array::i32s("water_type", seg_i32(|s| code(&WaterType::ALL, s.water))),
            Array::i32s("zone", seg_i32(|s| code(&SegmentZone::ALL, s.zone))),
            Array::i32s("phase", seg_i32(|s| s.phase as i32)),
            Array::f64s("flow", seg_f64(|s| s.flow)),
            Array::f64s("discharge", seg_f64(|s| s.discharge)),
            Array::f64s("water_depth", seg_f64(|s| s.depth)),
            Array::i32s("strahler_order", seg_i32(|s| s.strahler as i32)),
            Array::i32s("branch_id", seg_i32(|s| s.branch as i32)),
            Array::f64s("length", seg_f64(|s| s.length)),
        ],
        normals: None,
    };
    folder.write("network.vtp", ExportFormat::Vtk, |w| piece.write(w, frame))
}

/// `streams.vtp`: the surface streams, one line per segment, with the rendering attributes of
/// Table 1 (0 for pools and dry segments, which have none).
pub fn write_streams(folder: &mut Folder, frame: &Frame, streams: &Streams) -> Result<(), ExportError> {
    let (nodes, segments) = (&streams.nodes, &streams.segments);
    let seg_f64 = |f: &dyn Fn(&Segment) -> f64| segments.iter().map(f).collect::<Vec<_>>();
    let look = |f: fn(&karst_hydro::Look) -> f64| seg_f64(&|s| s.look.as_ref().map_or(0.0, f));
    let fall = |f: fn(&karst_streams::Fall) -> f64| seg_f64(&|s| s.fall.as_ref().map_or(0.0, f));
    let piece = Piece {
        points: Array::points(nodes.len(), |i| frame.world(nodes[i].position)),
        cell_section: "Lines",
        cells: segments.len(),
        connectivity: Array::connectivity(segments.len(), 2, |c, k| [segments[c].from, segments[c].to][k]),
        offsets: Array::offsets(segments.len(), 2),
        point_data: vec![
            Array::i32s("node_id", (1..=nodes.len() as i32).collect()),
            Array::f64s("elevation", nodes.iter().map(|n| frame.world(n.position)[2]).collect()),
            Array::i32s("role", nodes.iter().map(|n| code(&ROLES, n.role)).collect()),
            Array::f64s("source", nodes.iter().map(|n| n.source).collect()),
            Array::f64s("lateral", nodes.iter().map(|n| n.lateral).collect()),
            Array::f64s("inflow", nodes.iter().map(|n| n.inflow).collect()),
        ],
        cell_data: vec![
            Array::i32s("segment_id", (1..=segments.len() as i32).collect()),
            Array::i32s("motion", segments.iter().map(|s| code(&MOTIONS, s.motion)).collect()),
            Array::i32s("water_type", segments.iter().map(|s| code(&WaterType::ALL, s.water)).collect()),
            Array::f64s("flow", seg_f64(&|s| s.flow)),
            Array::f64s("flow_units", seg_f64(&|s| s.flow_units)),
            Array::f64s("slope", seg_f64(&|s| s.slope)),
            Array::f64s("speed", seg_f64(&|s| s.speed)),
            Array::f64s("width", seg_f64(&|s| s.width)),
            Array::f64s("water_depth", seg_f64(&|s| s.depth)),
            Array::f64s("length", seg_f64(&|s| streams.length(s))),
            Array::f64s("drop", fall(|f| f.drop)),
            Array::f64s("throw", fall(|f| f.throw)),
            Array::f64s("foam", look(|l| l.foam)),
            Array::f64s("rocks", look(|l| l.rocks)),
            Array::f64s("disturbance", look(|l| l.disturbance)),
            Array::f64s("particles", look(|l| l.particles)),
        ],
        normals: None,
    };
    folder.write("streams.vtp", ExportFormat::Vtk, |w| piece.write(w, frame))
}

/// `terrain.vtp`, `cave.vtp`, `water.vtp`: triangles with vertex normals.
pub fn write_meshes(folder: &mut Folder, frame: &Frame, surfaces: &Surfaces) -> Result<(), ExportError> {
    for s in &surfaces.list {
        let (surface, normals) = (s.surface, &s.normals);
        if surface.vertices.len() > i32::MAX as usize || surface.triangles.len() * 3 > i32::MAX as usize {
            return Err(ExportError::Unsupported(format!(
                "{}: too large for 32-bit VTK connectivity",
                s.name
            )));
        }
        let normals_array = Array {
            name: "Normals",
            kind: Kind::Float32,
            components: 3,
            tuples: normals.len(),
            write: Box::new(move |w: &mut dyn Write| {
                normals.iter().flatten().try_for_each(|c| w.write_all(&c.to_le_bytes()))
            }),
        };
        let piece = Piece {
            points: Array::points(surface.vertices.len(), |i| frame.world_f32(surface.vertices[i])),
            cell_section: "Polys",
            cells: surface.triangles.len(),
            connectivity: Array::connectivity(surface.triangles.len(), 3, |c, k| surface.triangles[c][k]),
            offsets: Array::offsets(surface.triangles.len(), 3),
            point_data: vec![normals_array],
            cell_data: Vec::new(),
            normals: Some("Normals"),
        };
        folder.write(&format!("{}.vtp", s.name), ExportFormat::VtkMeshes, |w| piece.write(w, frame))?;
    }
    Ok(())
}
