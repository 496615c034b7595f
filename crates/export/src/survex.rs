//! Survex (`network.svx`, processed by `cavern`, viewed in Aven): the conduit centrelines as a
//! survey inside `*begin karst`. Stations are the 1-based node ids; each segment is one
//! cartesian leg (easting, northing, altitude differences, metres); sinks and springs are
//! `*fix`ed at their world coordinates and marked `*entrance`; a part of the network reached
//! by neither is fixed at its lowest-numbered station, so that every station has a position.
//! Passage dimensions: one `*data passage` block per conduit, left = right = the half-width
//! (the radius) and up = down = the radius at each station. Segments from a node to itself
//! are left out: cavern would warn about a leg with the same station at both ends.

use karst_scene::params::ExportFormat;

use crate::ExportError;
use crate::folder::Folder;
use crate::frame::Frame;
use crate::network::{NetworkView, SegmentRecord};

/// `network.svx`.
pub fn write(folder: &mut Folder, frame: &Frame, net: &NetworkView) -> Result<(), ExportError> {
    folder.write("network.svx", ExportFormat::Survex, |w| {
        writeln!(w, "; karstgen conduit network: stations are 1-based node ids, metres, world coordinates")?;
        writeln!(w, "*begin karst")?;
        writeln!(w, "*title \"karstgen network\"")?;
        for (node, name) in fixed_stations(net) {
            let [x, y, z] = frame.world(net.nodes[node as usize].position);
            writeln!(w, "*fix {} {x:.3} {y:.3} {z:.3} ; {name}", node + 1)?;
            if name != "unconnected part" {
                writeln!(w, "*entrance {}", node + 1)?;
            }
        }
        writeln!(w, "*data cartesian from to easting northing altitude")?;
        for s in net.segments.iter().filter(|s| !s.is_loop()) {
            let [a, b] = s.nodes.map(|n| frame.world(net.nodes[n as usize].position));
            writeln!(
                w,
                "{} {} {:.3} {:.3} {:.3}",
                s.nodes[0] + 1,
                s.nodes[1] + 1,
                b[0] - a[0],
                b[1] - a[1],
                b[2] - a[2]
            )?;
        }
        for range in &net.conduits {
            let segments: Vec<&SegmentRecord> =
                net.segments[range.clone()].iter().filter(|s| !s.is_loop()).collect();
            let Some(last) = segments.last() else { continue };
            writeln!(w, "*data passage station left right up down")?;
            let stations =
                segments.iter().map(|s| (s.nodes[0], s.radius[0])).chain([(last.nodes[1], last.radius[1])]);
            for (node, r) in stations {
                writeln!(w, "{} {r:.2} {r:.2} {r:.2} {r:.2}", node + 1)?;
            }
        }
        writeln!(w, "*end karst")
    })
}

/// The stations to fix, with a comment: every sink and spring, then one station of each
/// connected part that has neither.
fn fixed_stations(net: &NetworkView) -> Vec<(u32, String)> {
    let mut fixed: Vec<(u32, String)> = net
        .sinks
        .iter()
        .map(|t| (t.node, format!("sink {}", t.name)))
        .chain(net.springs.iter().map(|t| (t.node, format!("spring {}", t.name))))
        .collect();
    fixed.sort_by_key(|(n, _)| *n);
    fixed.dedup_by_key(|(n, _)| *n);
    let part = net.parts();
    let mut has_fix = vec![false; net.nodes.len()];
    for (n, _) in &fixed {
        has_fix[part[*n as usize]] = true;
    }
    let used = used_nodes(net);
    for n in 0..net.nodes.len() {
        if used[n] && !has_fix[part[n]] {
            has_fix[part[n]] = true;
            fixed.push((n as u32, "unconnected part".into()));
        }
    }
    fixed
}

fn used_nodes(net: &NetworkView) -> Vec<bool> {
    let mut used = vec![false; net.nodes.len()];
    for s in net.segments.iter().filter(|s| !s.is_loop()) {
        for n in s.nodes {
            used[n as usize] = true;
        }
    }
    used
}
