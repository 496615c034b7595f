//! EPA SWMM 5 (`network.inp`, SWMM 5.2's engine and GUI): the network as a dynamic-wave model
//! of constant sink inflows draining to free outfalls at the springs.
//!
//! - Junctions at the network nodes, named by their 1-based node id; invert = the lowest
//!   conduit floor at the node, maximum depth up to the highest conduit crown there, surcharge
//!   depth up to the highest crown of the network (the rock is closed: phreatic conduits may be
//!   pressurized that far; lower it to the terrain to let water flood out).
//! - Conduits are the segments, named by their 1-based segment id and pointing downstream
//!   (conduit order when dry). Cross-section from the conduit type and the mean radius r of the
//!   segment's ends: `canyon` a closed rectangle 2r high and 1.2r wide, `bed` a closed
//!   rectangle 0.9r high and 2.4r wide (karstgen's canyon and bedding-plane sections), every
//!   other type a circle of diameter 2r. The centreline passes through the nodes. Segments
//!   steeper than `export.swmm_max_slope` (shafts) keep that slope and fall the rest at their
//!   lower junction, as drop structures are modelled in SWMM. Manning's n is `export.manning`.
//! - Each spring is a junction drained by a short conduit (`SPRING_outlet`) to a free outfall
//!   `SPRING` (an outfall may have one link only, and a spring may have several conduits).
//! - Sinks get constant inflows equal to karstgen's recharge in m³/s; pools (hydro's ponds,
//!   chambers) are storage units with the horizontal area of their widest conduit.
//! - Initial state: junctions hold hydro's water level, so that ponds and flooded conduits do
//!   not have to fill first (initial conduit flows made the engine's continuity worse: left
//!   at 0).

use std::collections::BTreeMap;
use std::f64::consts::PI;
use std::io::{self, Write};

use karst_geology::params::{ExportFormat, ExportParams};
use karst_hydro::Role;
use karst_skeleton::ConduitType;

use crate::ExportError;
use crate::folder::Folder;
use crate::frame::Frame;
use crate::network::{NetworkView, SegmentRecord};

/// A SWMM cross-section: its shape line and full height.
struct Section {
    shape: &'static str,
    height: f64,
    width: f64,
}

fn section(kind: ConduitType, r: f64) -> Section {
    match kind {
        ConduitType::Canyon => Section { shape: "RECT_CLOSED", height: 2.0 * r, width: 1.2 * r },
        ConduitType::Bed => Section { shape: "RECT_CLOSED", height: 0.9 * r, width: 2.4 * r },
        _ => Section { shape: "CIRCULAR", height: 2.0 * r, width: 0.0 },
    }
}

/// One conduit of the model: its ends in water order and their inverts.
struct Link<'a> {
    segment: &'a SegmentRecord,
    ends: [u32; 2],
    inverts: [f64; 2],
    section: Section,
}

/// The vertical layout of the model: conduit end inverts and the junctions around them.
struct Layout<'a> {
    links: Vec<Link<'a>>,
    invert: Vec<f64>,
    crown: Vec<f64>,
    top: f64,
}

/// Length below which a conduit is given this length (SWMM refuses zero-length conduits).
const MIN_LENGTH: f64 = 0.1;

fn layout<'a>(net: &'a NetworkView, frame: &Frame, max_slope: f64) -> Layout<'a> {
    let z = |n: u32| frame.world(net.nodes[n as usize].position)[2];
    let links: Vec<Link> = net
        .segments
        .iter()
        .filter(|s| !s.is_loop())
        .map(|s| {
            let section = section(s.conduit_type, 0.5 * (s.radius[0] + s.radius[1]));
            let ends = s.flow_ends();
            let mut inverts = ends.map(|n| z(n) - section.height / 2.0);
            let length = s.length.max(MIN_LENGTH);
            let drop = inverts[0] - inverts[1];
            if drop.abs() > max_slope * length {
                let (low, high) = if drop > 0.0 { (1, 0) } else { (0, 1) };
                inverts[low] = inverts[high] - max_slope * length;
            }
            Link { segment: s, ends, inverts, section }
        })
        .collect();
    let mut invert = vec![f64::INFINITY; net.nodes.len()];
    let mut crown = vec![f64::NEG_INFINITY; net.nodes.len()];
    for l in &links {
        for (n, i) in l.ends.iter().zip(l.inverts) {
            invert[*n as usize] = invert[*n as usize].min(i);
            crown[*n as usize] = crown[*n as usize].max(i + l.section.height);
        }
    }
    let top = crown.iter().copied().fold(f64::NEG_INFINITY, f64::max);
    Layout { links, invert, crown, top }
}

/// A SWMM name: no spaces.
fn name(text: &str) -> String {
    text.chars().map(|c| if c.is_whitespace() || c == ';' || c == '"' { '_' } else { c }).collect()
}

/// `network.inp`.
pub fn write(
    folder: &mut Folder,
    frame: &Frame,
    net: &NetworkView,
    params: &ExportParams,
) -> Result<(), ExportError> {
    let lay = layout(net, frame, params.swmm_max_slope);
    folder.write("network.inp", ExportFormat::Swmm, |w| {
        options(w, params.swmm_hours)?;
        nodes(w, net, &lay)?;
        conduits(w, net, &lay, params.manning)?;
        writeln!(w, "\n[INFLOWS]\n;;Node Constituent TimeSeries Type Mfactor Sfactor Baseline")?;
        for sink in &net.sinks {
            writeln!(w, "{} FLOW \"\" FLOW 1.0 1.0 {}", sink.node + 1, sink.discharge)?;
        }
        writeln!(w, "\n[REPORT]\nINPUT NO\nCONTROLS NO\nSUBCATCHMENTS NONE\nNODES ALL\nLINKS ALL")?;
        coordinates(w, frame, net, &lay)
    })
}

fn options(w: &mut dyn Write, hours: f64) -> io::Result<()> {
    let seconds = (hours * 3600.0).round() as u64;
    let (days, rest) = (seconds / 86_400, seconds % 86_400);
    let end = end_date(days);
    writeln!(
        w,
        "[TITLE]\nkarstgen conduit network: constant sink inflows to free outfalls at the springs (docs/exports.md)"
    )?;
    writeln!(
        w,
        "\n[OPTIONS]\nFLOW_UNITS CMS\nINFILTRATION HORTON\nFLOW_ROUTING DYNWAVE\nLINK_OFFSETS DEPTH"
    )?;
    writeln!(
        w,
        "START_DATE 01/01/2000\nSTART_TIME 00:00:00\nREPORT_START_DATE 01/01/2000\nREPORT_START_TIME 00:00:00"
    )?;
    writeln!(w, "END_DATE {end}\nEND_TIME {:02}:{:02}:{:02}", rest / 3600, rest % 3600 / 60, rest % 60)?;
    writeln!(
        w,
        "REPORT_STEP 00:15:00\nWET_STEP 00:15:00\nDRY_STEP 01:00:00\nROUTING_STEP 1\nVARIABLE_STEP 0.75"
    )?;
    writeln!(
        w,
        "INERTIAL_DAMPING PARTIAL\nNORMAL_FLOW_LIMITED BOTH\nSURCHARGE_METHOD EXTRAN\nMIN_SURFAREA 1.167"
    )?;
    writeln!(w, "HEAD_TOLERANCE 0.0015\nMAX_TRIALS 8\nTHREADS 1\nALLOW_PONDING NO\nSKIP_STEADY_STATE NO")
}

/// The date `days` after 1 January 2000 (mm/dd/yyyy), for runs shorter than a year.
fn end_date(days: u64) -> String {
    const MONTHS: [u64; 12] = [31, 29, 31, 30, 31, 30, 31, 31, 30, 31, 30, 31];
    let (mut month, mut day) = (0, days);
    while month < 11 && day >= MONTHS[month] {
        day -= MONTHS[month];
        month += 1;
    }
    format!("{:02}/{:02}/2000", month + 1, day + 1)
}

/// Depth with 4 decimals, never below what SWMM needs to hold the conduits: rounded up, plus
/// 1 mm so that SWMM's own unit conversions never find a crown above it.
fn up(x: f64) -> f64 {
    (x.max(0.0) * 1e4).ceil() / 1e4 + 0.001
}

fn nodes(w: &mut dyn Write, net: &NetworkView, lay: &Layout) -> io::Result<()> {
    let init = initial_depths(net, lay);
    let storage = storage_nodes(net);
    let used: Vec<bool> = (0..net.nodes.len()).map(|n| lay.invert[n].is_finite()).collect();
    let depth = |n: usize| up(lay.crown[n] - round4(lay.invert[n]));
    let surcharge = |n: usize| up(lay.top - lay.crown[n]);
    writeln!(w, "\n[JUNCTIONS]\n;;Name Elevation MaxDepth InitDepth SurDepth Aponded")?;
    for n in (0..net.nodes.len()).filter(|&n| used[n] && !storage.contains_key(&n)) {
        let d = depth(n);
        writeln!(w, "{} {:.4} {d:.4} {:.4} {:.4} 0", n + 1, lay.invert[n], init[n].min(d), surcharge(n))?;
    }
    writeln!(w, "\n[OUTFALLS]\n;;Name Elevation Type Gated")?;
    for spring in &net.springs {
        writeln!(w, "{} {:.4} FREE NO", name(&spring.name), lay.invert[spring.node as usize] - OUTLET_DROP)?;
    }
    writeln!(w, "\n[STORAGE]\n;;Name Elev MaxDepth InitDepth Shape A1 A2 A0 SurDepth Fevap")?;
    for (&n, &area) in storage.iter().filter(|(n, _)| used[**n]) {
        let d = depth(n);
        writeln!(
            w,
            "{} {:.4} {d:.4} {:.4} FUNCTIONAL 0 0 {area:.4} {:.4} 0",
            n + 1,
            lay.invert[n],
            init[n].min(d),
            surcharge(n)
        )?;
    }
    Ok(())
}

fn round4(x: f64) -> f64 {
    (x * 1e4).round() / 1e4
}

/// Drop of a spring's outlet conduit, metres.
const OUTLET_DROP: f64 = 0.01;

/// Pools (hydro's ponds and chambers) with the horizontal area of their widest conduit, m².
fn storage_nodes(net: &NetworkView) -> BTreeMap<usize, f64> {
    let mut pools = BTreeMap::new();
    for s in &net.segments {
        for (n, r) in s.nodes.iter().zip(s.radius) {
            let node = &net.nodes[*n as usize];
            if node.role == Role::Pool || s.conduit_type == ConduitType::Chamber {
                let area = pools.entry(*n as usize).or_insert(0.0f64);
                *area = area.max(PI * r * r);
            }
        }
    }
    for t in net.sinks.iter().chain(&net.springs) {
        pools.remove(&(t.node as usize));
    }
    pools
}

/// Water depth at each junction from hydro's water levels (0 where dry).
fn initial_depths(net: &NetworkView, lay: &Layout) -> Vec<f64> {
    let mut depth = vec![0.0f64; net.nodes.len()];
    for s in net.segments.iter().filter(|s| s.wet) {
        if let Some(level) = s.level {
            for (n, l) in s.nodes.iter().zip(level) {
                let n = *n as usize;
                depth[n] = depth[n].max(l - lay.invert[n]);
            }
        }
    }
    depth.iter().map(|d| d.max(0.0)).collect()
}

fn conduits(w: &mut dyn Write, net: &NetworkView, lay: &Layout, manning: f64) -> io::Result<()> {
    writeln!(w, "\n[CONDUITS]\n;;Name From To Length Roughness InOffset OutOffset InitFlow MaxFlow")?;
    for l in &lay.links {
        let [a, b] = l.ends.map(|n| n as usize);
        let offsets =
            [l.inverts[0] - round4(lay.invert[a]), l.inverts[1] - round4(lay.invert[b])].map(|o| o.max(0.0));
        let length = l.segment.length.max(MIN_LENGTH);
        writeln!(
            w,
            "{} {} {} {length:.4} {manning} {:.4} {:.4} 0 0",
            l.segment.id,
            a + 1,
            b + 1,
            offsets[0],
            offsets[1]
        )?;
    }
    for spring in &net.springs {
        let n = spring.node as usize;
        let length = (lay.crown[n] - lay.invert[n]).max(1.0);
        writeln!(
            w,
            "{}_outlet {} {} {length:.4} {manning} 0 0 0 0",
            name(&spring.name),
            n + 1,
            name(&spring.name)
        )?;
    }
    writeln!(w, "\n[XSECTIONS]\n;;Link Shape Geom1 Geom2 Geom3 Geom4 Barrels")?;
    for l in &lay.links {
        writeln!(
            w,
            "{} {} {:.4} {:.4} 0 0 1",
            l.segment.id, l.section.shape, l.section.height, l.section.width
        )?;
    }
    for spring in &net.springs {
        let n = spring.node as usize;
        writeln!(
            w,
            "{}_outlet CIRCULAR {:.4} 0 0 0 1",
            name(&spring.name),
            up(lay.crown[n] - lay.invert[n])
        )?;
    }
    Ok(())
}

fn coordinates(w: &mut dyn Write, frame: &Frame, net: &NetworkView, lay: &Layout) -> io::Result<()> {
    writeln!(w, "\n[COORDINATES]\n;;Node X Y")?;
    for (n, node) in net.nodes.iter().enumerate().filter(|(n, _)| lay.invert[*n].is_finite()) {
        let [x, y, _] = frame.world(node.position);
        writeln!(w, "{} {x:.3} {y:.3}", n + 1)?;
    }
    for spring in &net.springs {
        let [x, y, _] = frame.world(net.nodes[spring.node as usize].position);
        writeln!(w, "{} {:.3} {y:.3}", name(&spring.name), x + 1.0)?;
    }
    Ok(())
}
