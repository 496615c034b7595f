//! The network statistics on real caves and generated networks, beside karstnet 1.2.5.

use std::path::{Path, PathBuf};
use std::time::Instant;

use karst_metrics::{Network, characterize, readers};
use karst_stage::StageError;

use super::{median, scratch_dir};

/// Timing of karst-metrics (and karstnet, when available) on one network.
#[derive(Debug, Clone)]
pub struct NetworkTiming {
    pub name: String,
    pub nodes: usize,
    pub reduced_nodes: usize,
    /// Median seconds of `characterize`.
    pub ours: f64,
    /// karstnet's seconds for load + `characterize_graph()` + the extra metrics, timed inside
    /// Python (start-up and imports excluded; `None` without `KARSTNET_PYTHON`).
    pub karstnet: Option<f64>,
}

/// Times `characterize` on Sakany and Monachou (from `fixtures/caves`) and on
/// generated networks of about 7,000 and 10,000 nodes; karstnet too when `KARSTNET_PYTHON` is set.
pub fn time_networks(runs: usize) -> Result<Vec<NetworkTiming>, StageError> {
    let caves = Path::new("fixtures/caves");
    let scratch = scratch_dir(Path::new("networks"));
    std::fs::create_dir_all(&scratch)
        .map_err(|e| StageError::failure(format!("{}: {e}", scratch.display())))?;
    let mut cases: Vec<(String, Network, PathBuf)> = Vec::new();
    if let Ok(net) = readers::read_karstnet(&caves.join("Sakany")) {
        cases.push(("Sakany".into(), net, caves.join("Sakany")));
    }
    if let Ok(net) = readers::read_pline(&caves.join("Monachou.pl")) {
        cases.push(("Monachou".into(), net, caves.join("Monachou.pl")));
    }
    for (name, tree_nodes) in [("generated-7k", 6_400), ("generated-10k", 9_200)] {
        let net = generated_network(7, tree_nodes);
        let base = scratch.join(name);
        write_karstnet(&net, &base).map_err(|e| StageError::failure(format!("{}: {e}", base.display())))?;
        cases.push((name.into(), net, base));
    }
    let python = std::env::var("KARSTNET_PYTHON").ok();
    let mut timings = Vec::new();
    for (name, net, file) in cases {
        let metrics = characterize(&net).map_err(|e| StageError::input(format!("{name}: {e}")))?;
        let ours = median(
            (0..runs.max(1))
                .map(|_| {
                    let start = Instant::now();
                    let _ = characterize(&net);
                    start.elapsed().as_secs_f64()
                })
                .collect(),
        );
        let karstnet = python.as_deref().and_then(|p| karstnet_seconds(p, &file));
        timings.push(NetworkTiming {
            name,
            nodes: metrics.n_nodes_full,
            reduced_nodes: metrics.n_nodes_simpl,
            ours,
            karstnet,
        });
    }
    Ok(timings)
}

/// The mazes whose statistics are timed, where the simplified graph keeps most nodes and the
/// all-pairs traversals dominate (issues 15 and 40): a 200 × 200 grid (40,000 junctions), a
/// 100 × 100 grid of junctions joined by corridors of 12 stations (247,600 nodes, 10,000
/// junctions) and a 500 × 500 grid (250,000 junctions).
pub fn mazes() -> Vec<(&'static str, Network)> {
    vec![
        ("grid-40k", grid_maze(200, 0)),
        ("corridors-250k", grid_maze(100, 12)),
        ("grid-250k", grid_maze(500, 0)),
    ]
}

/// Times `characterize` on one maze: the median wall time of `runs` runs.
pub fn time_maze(name: &str, net: &Network, runs: usize) -> Result<NetworkTiming, StageError> {
    let mut seconds = Vec::new();
    let mut metrics = None;
    for _ in 0..runs.max(1) {
        let start = Instant::now();
        metrics = Some(characterize(net).map_err(|e| StageError::input(format!("{name}: {e}")))?);
        seconds.push(start.elapsed().as_secs_f64());
    }
    let metrics = metrics.expect("at least one run");
    Ok(NetworkTiming {
        name: name.into(),
        nodes: metrics.n_nodes_full,
        reduced_nodes: metrics.n_nodes_simpl,
        ours: median(seconds),
        karstnet: None,
    })
}

/// A `side` × `side` grid of junctions 10 m apart, each grid edge a corridor with `stations`
/// intermediate stations.
pub fn grid_maze(side: usize, stations: usize) -> Network {
    let mut nodes: Vec<[f64; 3]> =
        (0..side * side).map(|v| [(v % side) as f64 * 10.0, (v / side) as f64 * 10.0, 0.0]).collect();
    let mut links = Vec::new();
    let mut corridor = |a: usize, b: usize, nodes: &mut Vec<[f64; 3]>| {
        let mut previous = a;
        for k in 1..=stations {
            let t = k as f64 / (stations + 1) as f64;
            let (pa, pb) = (nodes[a], nodes[b]);
            nodes.push([0, 1, 2].map(|c| pa[c] + (pb[c] - pa[c]) * t));
            links.push([previous, nodes.len() - 1]);
            previous = nodes.len() - 1;
        }
        links.push([previous, b]);
    };
    for y in 0..side {
        for x in 0..side {
            let v = y * side + x;
            if x + 1 < side {
                corridor(v, v + 1, &mut nodes);
            }
            if y + 1 < side {
                corridor(v, v + side, &mut nodes);
            }
        }
    }
    Network { nodes, links }
}

/// karstnet's own time on `file` (load and metrics), as `karstnet_oracle.py` reports it.
fn karstnet_seconds(python: &str, file: &Path) -> Option<f64> {
    let script = Path::new("crates/metrics/tests/karstnet_oracle.py");
    let out = std::process::Command::new(python).arg(script).arg(file).output().ok()?;
    let stderr = String::from_utf8_lossy(&out.stderr);
    let line = stderr.lines().find_map(|l| l.strip_prefix("karstnet seconds: "))?;
    out.status.success().then(|| line.trim().parse().ok()).flatten()
}

/// A cave-like network: a random walk tree with long chains (each new station continues the
/// previous one with probability 0.9), plus loops closed between random stations.
fn generated_network(seed: u64, tree_nodes: usize) -> Network {
    let mut state = seed;
    let mut next = move || {
        state = state.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = state;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        ((z ^ (z >> 31)) >> 11) as f64 / (1u64 << 53) as f64
    };
    let mut nodes = vec![[0.0; 3]];
    let mut links = Vec::new();
    for i in 1..tree_nodes {
        let parent = if next() < 0.9 { i - 1 } else { (next() * i as f64) as usize };
        let p = nodes[parent];
        nodes.push([p[0] + 10.0 * (next() - 0.5), p[1] + 10.0 * (next() - 0.5), p[2] + 2.0 * (next() - 0.5)]);
        links.push([parent, i]);
    }
    for _ in 0..tree_nodes / 25 {
        let (a, b) = ((next() * tree_nodes as f64) as usize, (next() * tree_nodes as f64) as usize);
        if a == b {
            continue;
        }
        let stations = (next() * 5.0) as usize;
        let mut previous = a;
        for k in 1..=stations {
            let t = k as f64 / (stations + 1) as f64;
            let (pa, pb) = (nodes[a], nodes[b]);
            nodes.push([0, 1, 2].map(|c| pa[c] + (pb[c] - pa[c]) * t + (next() - 0.5)));
            links.push([previous, nodes.len() - 1]);
            previous = nodes.len() - 1;
        }
        links.push([previous, b]);
    }
    Network { nodes, links }
}

/// karstnet's `{base}_nodes.dat` and `{base}_links.dat` (1-based links).
fn write_karstnet(net: &Network, base: &Path) -> std::io::Result<()> {
    let mut nodes = String::new();
    for [x, y, z] in &net.nodes {
        nodes += &format!("{x} {y} {z}\n");
    }
    let mut links = String::new();
    for [a, b] in &net.links {
        links += &format!("{} {}\n", a + 1, b + 1);
    }
    let name = base.file_name().map(|n| n.to_string_lossy().into_owned()).unwrap_or_default();
    std::fs::write(base.with_file_name(format!("{name}_nodes.dat")), nodes)?;
    std::fs::write(base.with_file_name(format!("{name}_links.dat")), links)
}
