//! Export in karstnet's format: `BASE_nodes.dat` (x y z per line) and `BASE_links.dat`
//! (two 1-based node indices per line), without self-loops or duplicate links, which karstnet
//! does not tolerate; plus `BASE_nodes.csv`, the attributes of every node in the same order:
//! 1-based id, position, sample, key point, zone, the largest radius of the conduits through
//! it and the earliest phase among them.

use std::path::Path;

use karst_artifact::atomic;

use crate::{Skeleton, Zone};

/// Writes `{base}_nodes.dat` and `{base}_links.dat`.
pub fn write(skeleton: &Skeleton, base: &Path) -> std::io::Result<()> {
    let with_suffix = |suffix: &str| {
        let mut name = base.file_name().unwrap_or_default().to_os_string();
        name.push(suffix);
        base.with_file_name(name)
    };
    atomic::write_with(&with_suffix("_nodes.dat"), |w| {
        for node in &skeleton.nodes {
            let [x, y, z] = node.position;
            writeln!(w, "{x} {y} {z}")?;
        }
        Ok(())
    })?;
    let mut links = skeleton.links();
    links.retain(|[a, b]| a != b);
    links.sort_unstable();
    links.dedup();
    atomic::write_with(&with_suffix("_links.dat"), |w| {
        for [a, b] in links {
            writeln!(w, "{} {}", a + 1, b + 1)?;
        }
        Ok(())
    })?;
    let (radius, phase) = node_attributes(skeleton);
    atomic::write_with(&with_suffix("_nodes.csv"), |w| {
        writeln!(w, "id,x,y,z,sample,keypoint,zone,radius,phase")?;
        for (i, node) in skeleton.nodes.iter().enumerate() {
            let [x, y, z] = node.position;
            let zone = match node.zone {
                Zone::Vadose => "vadose",
                Zone::Phreatic => "phreatic",
            };
            let keypoint = node
                .keypoint
                .as_deref()
                .map(|k| format!("\"{}\"", k.replace('"', "\"\"")))
                .unwrap_or_default();
            writeln!(
                w,
                "{},{x},{y},{z},{},{keypoint},{zone},{},{}",
                i + 1,
                node.sample,
                radius[i],
                phase[i]
            )?;
        }
        Ok(())
    })
}

/// The largest radius and the earliest phase of the conduits through each node.
fn node_attributes(skeleton: &Skeleton) -> (Vec<f64>, Vec<u32>) {
    let mut radius = vec![0.0f64; skeleton.nodes.len()];
    let mut phase = vec![u32::MAX; skeleton.nodes.len()];
    for conduit in &skeleton.conduits {
        for (&node, &r) in conduit.nodes.iter().zip(&conduit.radius) {
            radius[node as usize] = radius[node as usize].max(r);
            phase[node as usize] = phase[node as usize].min(conduit.phase);
        }
    }
    for p in &mut phase {
        if *p == u32::MAX {
            *p = 0;
        }
    }
    (radius, phase)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::{Conduit, ConduitType, Node};

    #[test]
    fn export_is_one_based_without_self_loops_or_duplicates_with_attributes() {
        let node = |x: f64, k: Option<&str>| Node {
            position: [x, 0.0, 0.0],
            sample: x as u32,
            keypoint: k.map(String::from),
            zone: Zone::Vadose,
        };
        let conduit = |nodes: Vec<u32>, r: f64, phase: u32| Conduit {
            radius: vec![r; nodes.len()],
            types: vec![ConduitType::Canyon; nodes.len() - 1],
            nodes,
            phase,
            keypoints: Vec::new(),
            profile: Vec::new(),
        };
        let skeleton = Skeleton {
            nodes: vec![node(0.0, Some("a, b")), node(1.0, None), node(2.0, None)],
            conduits: vec![conduit(vec![0, 1, 1, 2], 1.0, 1), conduit(vec![2, 1], 3.0, 0)],
            routes: Vec::new(),
            derived: Default::default(),
        };
        let dir = karst_testkit::scratch("karstnet");
        write(&skeleton, &dir.join("net")).unwrap();
        let links = std::fs::read_to_string(dir.join("net_links.dat")).unwrap();
        assert_eq!(links, "1 2\n2 3\n");
        let csv = std::fs::read_to_string(dir.join("net_nodes.csv")).unwrap();
        let rows: Vec<&str> = csv.lines().collect();
        assert_eq!(rows[1], "1,0,0,0,0,\"a, b\",vadose,1,1");
        assert_eq!(rows[2], "2,1,0,0,1,,vadose,3,0");
    }
}
