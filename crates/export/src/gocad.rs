//! GOCAD ASCII objects (SKUA-Gocad, and karstnet's reader): the network as a PLine
//! (`network.pl`), the samples as a VSet (`samples.vs`), the meshes as TSurfs (`terrain.ts`,
//! `cave.ts`, `water.ts`). World coordinates, metres, z up (`ZPOSITIVE Elevation`).
//!
//! PLine: one `ILINE` per conduit; a node's first appearance is a `PVRTX` with properties, its
//! later ones `ATOM`s of it (which is how GOCAD and karstnet join lines at a junction). GOCAD
//! keeps properties on vertices only, so a vertex carries its node's properties and those of the
//! segment that leaves it along its line (the last vertex: the segment that reaches it); a
//! junction vertex keeps the values of the first line through it. The exact per-segment values
//! are in network.vtp and segments.csv. Segments from a node to itself are left out (karstnet
//! would corrupt its branches). Lines are written with single spaces: karstnet 1.2.5 splits
//! vertex lines on one space.

use std::io::{self, Write};

use karst_geology::Geology;
use karst_hydro::WaterType;
use karst_sampling::{Samples, Tag};
use karst_scene::params::ExportFormat;
use karst_skeleton::{ConduitType, Zone};

use crate::ExportError;
use crate::folder::{Folder, Surfaces};
use crate::frame::Frame;
use crate::network::{NetworkView, NodeKind, SegmentRecord, SegmentZone, code};

fn header(w: &mut dyn Write, kind: &str, name: &str) -> io::Result<()> {
    writeln!(w, "GOCAD {kind} 1\nHEADER {{\nname:{name}\n}}")?;
    writeln!(w, "GOCAD_ORIGINAL_COORDINATE_SYSTEM\nNAME Default\nAXIS_NAME \"X\" \"Y\" \"Z\"")?;
    writeln!(w, "AXIS_UNIT \"m\" \"m\" \"m\"\nZPOSITIVE Elevation\nEND_ORIGINAL_COORDINATE_SYSTEM")
}

fn properties(w: &mut dyn Write, names: &[&str]) -> io::Result<()> {
    writeln!(w, "PROPERTIES {}", names.join(" "))?;
    writeln!(w, "ESIZES {}", vec!["1"; names.len()].join(" "))
}

const PLINE_PROPERTIES: [&str; 14] = [
    "node_id",
    "radius",
    "node_kind",
    "node_zone",
    "segment_id",
    "conduit_id",
    "conduit_type",
    "water_type",
    "zone",
    "phase",
    "discharge",
    "water_depth",
    "strahler_order",
    "branch_id",
];

/// `network.pl`.
pub fn write_pline(folder: &mut Folder, frame: &Frame, net: &NetworkView) -> Result<(), ExportError> {
    folder.write("network.pl", ExportFormat::Gocad, |w| {
        header(w, "PLine", "network")?;
        properties(w, &PLINE_PROPERTIES)?;
        let mut vertex_of = vec![0u64; net.nodes.len()];
        let mut next = 0u64;
        for range in &net.conduits {
            let segments: Vec<&SegmentRecord> =
                net.segments[range.clone()].iter().filter(|s| !s.is_loop()).collect();
            let Some(last) = segments.last() else { continue };
            writeln!(w, "ILINE")?;
            let stops = segments.iter().map(|s| (s.nodes[0], *s)).chain([(last.nodes[1], *last)]);
            let mut previous = None;
            for (node, segment) in stops {
                next += 1;
                if vertex_of[node as usize] == 0 {
                    vertex_of[node as usize] = next;
                    write_pvrtx(w, frame, net, next, node, segment)?;
                } else {
                    writeln!(w, "ATOM {next} {}", vertex_of[node as usize])?;
                }
                if let Some(p) = previous {
                    writeln!(w, "SEG {p} {next}")?;
                }
                previous = Some(next);
            }
        }
        writeln!(w, "END")
    })
}

fn write_pvrtx(
    w: &mut dyn Write,
    frame: &Frame,
    net: &NetworkView,
    id: u64,
    node: u32,
    s: &SegmentRecord,
) -> io::Result<()> {
    let n = &net.nodes[node as usize];
    let [x, y, z] = frame.world(n.position);
    write!(w, "PVRTX {id} {x} {y} {z} {} {} {}", node + 1, n.radius, code(&NodeKind::ALL, n.kind))?;
    write!(w, " {} {} {}", code(&[Zone::Vadose, Zone::Phreatic], n.zone), s.id, s.conduit)?;
    write!(w, " {} {}", code(&ConduitType::ALL, s.conduit_type), code(&WaterType::ALL, s.water))?;
    write!(w, " {} {} {} {}", code(&SegmentZone::ALL, s.zone), s.phase, s.discharge, s.depth)?;
    writeln!(w, " {} {}", s.strahler, s.branch)
}

/// The class of a sample and its 1-based index within the class (0 for the volume).
fn region(tag: Tag) -> (u32, u32) {
    match tag {
        Tag::Volume => (0, 0),
        Tag::Horizon(i) => (1, i + 1),
        Tag::WaterTable(i) => (2, i + 1),
        Tag::Fault(i) => (3, i + 1),
        Tag::KeyPoint(i) => (4, i + 1),
    }
}

/// `samples.vs`: every sample with its region (0 volume, 1 horizon, 2 water table, 3 fault,
/// 4 key point), the 1-based index of its surface or key point, and, when the scene's geology
/// is known, the 1-based index of the rock layer holding it (0: none).
pub fn write_vset(
    folder: &mut Folder,
    frame: &Frame,
    samples: &Samples,
    geology: Option<&Geology>,
) -> Result<(), ExportError> {
    folder.write("samples.vs", ExportFormat::Gocad, |w| {
        header(w, "VSet", "samples")?;
        let names: &[&str] =
            if geology.is_some() { &["region", "surface", "layer"] } else { &["region", "surface"] };
        properties(w, names)?;
        for (i, (p, tag)) in samples.positions.iter().zip(&samples.tags).enumerate() {
            let [x, y, z] = frame.world(*p);
            let (region, surface) = region(*tag);
            write!(w, "PVRTX {} {x} {y} {z} {region} {surface}", i + 1)?;
            match geology {
                Some(geology) => writeln!(w, " {}", layer(geology, *p))?,
                None => writeln!(w)?,
            }
        }
        writeln!(w, "END")
    })
}

fn layer(geology: &Geology, p: [f64; 3]) -> usize {
    let p = glam::DVec3::from_array(p);
    geology.layers.iter().position(|l| l.contains(p, geology)).map_or(0, |i| i + 1)
}

/// `terrain.ts`, `cave.ts`, `water.ts`: one TFACE each, 1-based vertex ids.
pub fn write_tsurfs(folder: &mut Folder, frame: &Frame, surfaces: &Surfaces) -> Result<(), ExportError> {
    for s in &surfaces.list {
        folder.write(&format!("{}.ts", s.name), ExportFormat::GocadMeshes, |w| {
            header(w, "TSurf", s.name)?;
            writeln!(w, "TFACE")?;
            for (i, v) in s.surface.vertices.iter().enumerate() {
                let [x, y, z] = frame.world_f32(*v);
                writeln!(w, "VRTX {} {x} {y} {z}", i + 1)?;
            }
            for [a, b, c] in &s.surface.triangles {
                writeln!(w, "TRGL {} {} {}", a + 1, b + 1, c + 1)?;
            }
            writeln!(w, "END")
        })?;
    }
    Ok(())
}
