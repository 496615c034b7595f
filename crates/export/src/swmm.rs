//! EPA SWMM 5 (`network.inp`, SWMM 5.2's engine and GUI): the network as a dynamic-wave model
//! of constant sink inflows draining to free outfalls at the springs, started at its own
//! steady state.
//!
//! - `swmm/model.rs`: the model as numbers (junctions, storage units, outfalls, conduits with
//!   their sections, offsets and drops, inflows);
//! - `swmm/chains.rs`: the chains of short segments merged into conduits the engine can route;
//! - `swmm/section.rs`: the cross-sections and their open-channel hydraulics;
//! - `swmm/steady.rs`: the steady state of hydro's discharges, which the model starts at
//!   (initial depths and flows), so that the engine's continuity balance does not count the
//!   filling of the network as an error, with the roughness of split conduits and the closed
//!   relict conduits that make the engine keep hydro's flows;
//! - this file writes the `.inp` sections.

mod chains;
mod model;
mod section;
mod steady;

use std::io::{self, Write};

use karst_scene::params::{ExportFormat, ExportParams};

use crate::ExportError;
use crate::folder::Folder;
use crate::frame::Frame;
use crate::network::NetworkView;
use model::{Model, NodeKind};
use steady::SteadyState;

/// `network.inp`.
pub fn write(
    folder: &mut Folder,
    frame: &Frame,
    net: &NetworkView,
    params: &ExportParams,
) -> Result<(), ExportError> {
    let model = model::build(net, frame, params);
    let state = steady::steady_state(&model, params.manning);
    let model = model.along(&state.flow);
    folder.write("network.inp", ExportFormat::Swmm, |w| {
        options(w, params.swmm_hours)?;
        nodes(w, &model, &state)?;
        conduits(w, &model, &state)?;
        writeln!(w, "\n[INFLOWS]\n;;Node Constituent TimeSeries Type Mfactor Sfactor Baseline")?;
        for &(node, flow) in &model.inflows {
            writeln!(w, "{} FLOW \"\" FLOW 1.0 1.0 {flow}", model.nodes[node].name)?;
        }
        writeln!(w, "\n[REPORT]\nINPUT NO\nCONTROLS NO\nSUBCATCHMENTS NONE\nNODES ALL\nLINKS ALL")?;
        coordinates(w, &model)
    })
}

/// The `[OPTIONS]`. `NORMAL_FLOW_LIMITED FROUDE`: SWMM caps a conduit's flow at its normal
/// flow only where the flow is supercritical at its upstream end, not also wherever the water
/// surface is flatter than the floor (`SLOPE`, in SWMM's default `BOTH`). On a flat or nearly
/// flat floor (horizontal passages in a bedding plane, which SWMM gives its minimum drop of
/// 0.001 ft) the normal flow is a small fraction of the discharge, and the slope rule switches
/// the conduit between its routed flow and that fraction each time a ripple makes the
/// downstream depth exceed the upstream one: an oscillation that never settles.
/// `INERTIAL_DAMPING FULL`: the momentum equation without its inertial terms (as SWMM already
/// does in full conduits): they vanish in the steady state the model starts at, and in the
/// nearly still water of a pond (wide conduits, little friction) they sustain a growing
/// seiche that reaches the spring.
/// `LENGTHENING_STEP 0.5`: the engine lengthens, for its own computation, every conduit that a
/// full-flow wave (velocity plus √(g·depth)) crosses in less than the routing step, as the
/// Courant condition asks and its variable step does not enforce for full conduits (the `.inp`
/// keeps the true lengths). Passage profiles give rooms 10–30 m high merged into conduits of
/// 2–7 m between sills; under the water table they are full, and at a step of 0.5 s they
/// sloshed by up to ±1.4 m³/s (branchwork's spring ±2 %, never settling).
/// `MAX_TRIALS 20`: the trials of a routing step's iteration for the heads (SWMM's default 8).
/// Along profiled passages a room's node sits between pinched conduits, and within 8 trials its
/// head does not always reach `HEAD_TOLERANCE`: the step then ends unconverged and loses water
/// (branchwork with `passage_detail = "full"`: a flow-routing continuity error of 1.14 %, the
/// spring 3.5 % under hydro's discharge; with 20 trials 0.09 % and 0.4 %, the same run time).
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
        "REPORT_STEP 00:15:00\nWET_STEP 00:15:00\nDRY_STEP 01:00:00\nROUTING_STEP 0.5\nVARIABLE_STEP 0.75\nLENGTHENING_STEP 0.5"
    )?;
    writeln!(
        w,
        "INERTIAL_DAMPING FULL\nNORMAL_FLOW_LIMITED FROUDE\nSURCHARGE_METHOD EXTRAN\nMIN_SURFAREA 1.167"
    )?;
    writeln!(w, "HEAD_TOLERANCE 0.0015\nMAX_TRIALS 20\nTHREADS 1\nALLOW_PONDING NO\nSKIP_STEADY_STATE NO")
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

fn nodes(w: &mut dyn Write, model: &Model, state: &SteadyState) -> io::Result<()> {
    let of_kind = |kind: fn(&NodeKind) -> bool| {
        model.nodes.iter().zip(&state.depth).filter(move |(n, _)| kind(&n.kind))
    };
    writeln!(w, "\n[JUNCTIONS]\n;;Name Elevation MaxDepth InitDepth SurDepth Aponded")?;
    for (n, init) in of_kind(|k| *k == NodeKind::Junction) {
        writeln!(w, "{} {:.4} {:.4} {init:.4} {:.4} 0", n.name, n.invert, n.depth, n.surcharge)?;
    }
    writeln!(w, "\n[OUTFALLS]\n;;Name Elevation Type Gated")?;
    for (n, _) in of_kind(|k| *k == NodeKind::Outfall) {
        writeln!(w, "{} {:.4} FREE NO", n.name, n.invert)?;
    }
    writeln!(w, "\n[STORAGE]\n;;Name Elev MaxDepth InitDepth Shape A1 A2 A0 SurDepth Fevap")?;
    for (n, init) in of_kind(|k| matches!(k, NodeKind::Storage(_))) {
        let NodeKind::Storage(area) = n.kind else { continue };
        writeln!(
            w,
            "{} {:.4} {:.4} {init:.4} FUNCTIONAL 0 0 {area:.4} {:.4} 0",
            n.name, n.invert, n.depth, n.surcharge
        )?;
    }
    Ok(())
}

/// The `MaxFlow` of a closed conduit, m³/s (SWMM reads 0 as no limit).
const CLOSED_FLOW: f64 = 1e-6;

fn conduits(w: &mut dyn Write, model: &Model, state: &SteadyState) -> io::Result<()> {
    writeln!(w, "\n[CONDUITS]\n;;Name From To Length Roughness InOffset OutOffset InitFlow MaxFlow")?;
    for (k, c) in model.conduits.iter().enumerate() {
        let [a, b] = c.ends.map(|n| &model.nodes[n].name);
        let flow = if state.starts_flowing[k] { state.flow[k].abs() } else { 0.0 };
        let max_flow = if state.closed[k] { CLOSED_FLOW } else { 0.0 };
        writeln!(
            w,
            "{} {a} {b} {:.4} {:.6} {:.4} {:.4} {flow:.6} {max_flow}",
            c.name, c.length, state.roughness[k], c.offsets[0], c.offsets[1]
        )?;
    }
    writeln!(w, "\n[XSECTIONS]\n;;Link Shape Geom1 Geom2 Geom3 Geom4 Barrels")?;
    for c in &model.conduits {
        let s = &c.section;
        writeln!(w, "{} {} {:.4} {:.4} 0 0 1", c.name, s.keyword(), s.height, s.width)?;
    }
    Ok(())
}

fn coordinates(w: &mut dyn Write, model: &Model) -> io::Result<()> {
    writeln!(w, "\n[COORDINATES]\n;;Node X Y")?;
    for n in &model.nodes {
        writeln!(w, "{} {:.3} {:.3}", n.name, n.xy[0], n.xy[1])?;
    }
    writeln!(w, "\n[VERTICES]\n;;Link X Y")?;
    for c in &model.conduits {
        for [x, y] in &c.vertices {
            writeln!(w, "{} {x:.3} {y:.3}", c.name)?;
        }
    }
    Ok(())
}
