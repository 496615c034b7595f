//! CSV export for flow models: `hydro_nodes.csv` (id, x, y, z, kind, diameter) and
//! `hydro_links.csv` (id, from, to, length, diameter, flow), the node/link tables that SWMM,
//! MODFLOW-CFP and openKARST converters read. Ids are 1-based, as in every table karstgen
//! writes (node `i` of skeleton.json is id `i + 1`), so that `karst-metrics --csv` reads them
//! with the other exports. Links are the wet and dry segments, directed
//! downstream (dry ones in conduit order); kind is inlet (sink), outlet (spring) or junction;
//! diameters are in metres (a node takes its widest conduit), flows in m³/s.

use std::fmt::Write as _;
use std::path::Path;

use glam::DVec3;

use karst_skeleton::Skeleton;

use crate::payload::{Hydro, Role};

/// File names, beside hydro.json.
pub const NODES: &str = "hydro_nodes.csv";
pub const LINKS: &str = "hydro_links.csv";

/// The two tables as text: (nodes, links).
pub fn tables(skeleton: &Skeleton, hydro: &Hydro) -> (String, String) {
    let mut diameter = vec![0.0f64; skeleton.nodes.len()];
    let mut links = String::from("id,from,to,length,diameter,flow\n");
    let mut id = 1;
    for (conduit, water) in skeleton.conduits.iter().zip(&hydro.conduits) {
        let radii = water.radius.as_ref().unwrap_or(&conduit.radius);
        for (i, (w, s)) in conduit.nodes.windows(2).zip(&water.segments).enumerate() {
            for (n, r) in [(w[0], radii[i]), (w[1], radii[i + 1])] {
                diameter[n as usize] = diameter[n as usize].max(2.0 * r);
            }
            let (from, to) = if s.downstream {
                (w[0], w[1])
            } else if s.flow > 0.0 {
                (w[1], w[0])
            } else {
                (w[0], w[1])
            };
            let [a, b] = [from, to].map(|n| DVec3::from_array(skeleton.nodes[n as usize].position));
            let d = radii[i] + radii[i + 1];
            let _ = writeln!(links, "{id},{},{},{},{d},{}", from + 1, to + 1, a.distance(b), s.discharge);
            id += 1;
        }
    }
    let mut nodes = String::from("id,x,y,z,kind,diameter\n");
    for (i, (node, water)) in skeleton.nodes.iter().zip(&hydro.nodes).enumerate() {
        let kind = match water.role {
            Role::Source => "inlet",
            Role::Well => "outlet",
            _ => "junction",
        };
        let [x, y, z] = node.position;
        let _ = writeln!(nodes, "{},{x},{y},{z},{kind},{}", i + 1, diameter[i]);
    }
    (nodes, links)
}

/// Writes the two tables into `dir`.
pub fn write(dir: &Path, skeleton: &Skeleton, hydro: &Hydro) -> std::io::Result<()> {
    let (nodes, links) = tables(skeleton, hydro);
    karst_artifact::atomic::write_bytes(&dir.join(NODES), nodes.as_bytes())?;
    karst_artifact::atomic::write_bytes(&dir.join(LINKS), links.as_bytes())
}
