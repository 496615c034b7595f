//! Export in karstnet's format: `BASE_nodes.dat` (x y z per line) and `BASE_links.dat`
//! (two 1-based node indices per line), without self-loops or duplicate links, which karstnet
//! does not tolerate.

use std::path::Path;

use karst_artifact::atomic;

use crate::Skeleton;

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
    links.sort_unstable();
    links.dedup();
    atomic::write_with(&with_suffix("_links.dat"), |w| {
        for [a, b] in links {
            writeln!(w, "{} {}", a + 1, b + 1)?;
        }
        Ok(())
    })
}
