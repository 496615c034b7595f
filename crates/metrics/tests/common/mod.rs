//! Helpers shared by the integration tests: data location, tolerant comparison of metric sets,
//! a seeded random cave generator and a karstnet-format writer.
#![allow(dead_code)] // each test binary uses a different subset

use std::collections::BTreeMap;
use std::fmt::Write as _;
use std::path::{Path, PathBuf};

use karst_metrics::{Metrics, Network};

/// `fixtures/caves`: the two real surveyed caves (CC0) and their expected metrics.
pub fn caves_dir() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../../fixtures/caves")
}

/// Metrics as a key → value map.
pub fn as_map(m: &Metrics) -> BTreeMap<String, f64> {
    m.to_pairs().into_iter().map(|(k, v)| (k.to_string(), v)).collect()
}

/// Whether `a` and `b` agree within `rel` relative, or 1e-12 absolute near 0. Undefined values
/// (NaN, ±∞) only equal undefined values: JSON writes them all as null.
pub fn close(a: f64, b: f64, rel: f64) -> bool {
    if !a.is_finite() || !b.is_finite() {
        return a == b || (!a.is_finite() && !b.is_finite() && (a.is_nan() || b.is_nan()));
    }
    let diff = (a - b).abs();
    a == b || diff <= rel * a.abs().max(b.abs()) || diff <= 1e-12
}

/// Asserts that both maps have the same keys (minus `skip`) and values within `rel`.
pub fn assert_same(
    ours: &BTreeMap<String, f64>,
    theirs: &BTreeMap<String, f64>,
    rel: f64,
    skip: &[&str],
    what: &str,
) {
    let keys = |m: &BTreeMap<String, f64>| -> Vec<String> {
        m.keys().filter(|k| !skip.contains(&k.as_str())).cloned().collect()
    };
    assert_eq!(keys(ours), keys(theirs), "{what}: key sets differ");
    let bad: Vec<String> = keys(ours)
        .into_iter()
        .filter(|k| !close(ours[k], theirs[k], rel))
        .map(|k| format!("  {k}: ours {:e} vs {:e}", ours[&k], theirs[&k]))
        .collect();
    assert!(bad.is_empty(), "{what}: metrics differ beyond {rel:e}:\n{}", bad.join("\n"));
}

/// Parses a JSON object of numbers (null = NaN) into a map.
pub fn json_map(value: &serde_json::Value) -> BTreeMap<String, f64> {
    value
        .as_object()
        .expect("a JSON object")
        .iter()
        .map(|(k, v)| (k.clone(), v.as_f64().unwrap_or(f64::NAN)))
        .collect()
}

/// SplitMix64: a tiny seeded generator, enough for test data.
pub struct SplitMix(u64);

impl SplitMix {
    pub fn new(seed: u64) -> Self {
        Self(seed)
    }

    pub fn next_u64(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    }

    /// Uniform in [0, 1).
    pub fn unit(&mut self) -> f64 {
        (self.next_u64() >> 11) as f64 / (1u64 << 53) as f64
    }

    /// Uniform in `0..n` (n > 0).
    pub fn below(&mut self, n: usize) -> usize {
        (self.next_u64() % n as u64) as usize
    }

    pub fn chance(&mut self, p: f64) -> bool {
        self.unit() < p
    }

    /// Random permutation of `0..n`.
    pub fn permutation(&mut self, n: usize) -> Vec<usize> {
        let mut p: Vec<usize> = (0..n).collect();
        for i in (1..n).rev() {
            p.swap(i, self.below(i + 1));
        }
        p
    }
}

/// Shape of a generated cave.
#[derive(Debug, Clone, Copy)]
pub struct CaveSpec {
    /// Nodes of the main tree (loops, conduits and extra components add more).
    pub tree_nodes: usize,
    /// Probability that a new tree node continues the previous one (long degree-2 chains).
    pub chain_bias: f64,
    /// Loops closed by a chain between two random nodes of the tree.
    pub loops: usize,
    /// Pairs of parallel conduits between a node and a new junction.
    pub parallel_pairs: usize,
    /// Closed conduits that start and end at the same node.
    pub looping_branches: usize,
    /// Round coordinates to multiples of 0.5 (creates exact bin-edge azimuths and vertical edges).
    pub grid: bool,
    /// Add an isolated cycle component (regular polygon) and a small tree component.
    pub extra_components: bool,
}

/// A random 3D cave network: a tree with chains, loops, parallel conduits, looping branches,
/// a dead end that comes back to its start point (coincident branch ends), duplicate links and
/// unused nodes, optionally extra components.
pub fn random_cave(seed: u64, spec: CaveSpec) -> Network {
    let mut g = Gen { rng: SplitMix::new(seed), nodes: Vec::new(), links: Vec::new(), grid: spec.grid };
    g.nodes.push([0.0, 0.0, 0.0]);
    for i in 1..spec.tree_nodes {
        let parent = if g.rng.chance(spec.chain_bias) { i - 1 } else { g.rng.below(i) };
        let p = g.step_from(parent);
        g.nodes.push(p);
        g.links.push([parent, i]);
    }
    for _ in 0..spec.loops {
        let (a, b) = (g.rng.below(spec.tree_nodes), g.rng.below(spec.tree_nodes));
        if a != b {
            let len = g.rng.below(5);
            g.chain(a, b, len);
        }
    }
    for k in 0..spec.parallel_pairs {
        let a = g.rng.below(spec.tree_nodes);
        let b = g.grow(a);
        let (first, second) = (g.rng.below(4) + 1, if k % 2 == 0 { 0 } else { g.rng.below(5) + 1 });
        g.chain(a, b, first);
        g.chain(a, b, second);
        let tail = g.grow(b);
        g.links.push([b, tail]);
    }
    for _ in 0..spec.looping_branches {
        let a = g.rng.below(spec.tree_nodes);
        let len = g.rng.below(6) + 2;
        g.chain(a, a, len);
    }
    // A dead end whose far end sits exactly on its start: tortuosity NaN.
    let a = g.rng.below(spec.tree_nodes);
    let (p1, p2) = (g.grow(a), g.grow(a));
    let back = g.add(g.nodes[a]);
    g.links.extend([[a, p1], [p1, p2], [p2, back]]);
    if spec.extra_components {
        let m = 3 + g.rng.below(8);
        g.isolated_cycle(m);
        g.small_tree(6);
    }
    // Duplicate links (one reversed) and nodes in no link.
    let dup = g.links[g.rng.below(g.links.len())];
    g.links.push(dup);
    g.links.push([dup[1], dup[0]]);
    for _ in 0..3 {
        g.nodes.push([1e4, 1e4, 1e4]);
    }
    Network { nodes: g.nodes, links: g.links }
}

struct Gen {
    rng: SplitMix,
    nodes: Vec<[f64; 3]>,
    links: Vec<[usize; 2]>,
    grid: bool,
}

impl Gen {
    fn round(&self, v: f64) -> f64 {
        if self.grid { (v * 2.0).round() / 2.0 } else { v }
    }

    /// A new node one random step away from `from`.
    fn grow(&mut self, from: usize) -> usize {
        let p = self.step_from(from);
        self.add(p)
    }

    fn step_from(&mut self, from: usize) -> [f64; 3] {
        let [x, y, z] = self.nodes[from];
        let len = 1.0 + 9.0 * self.rng.unit();
        let azimuth = std::f64::consts::TAU * self.rng.unit();
        let dip = if self.rng.chance(0.03) { 1.0 } else { 0.4 * (self.rng.unit() - 0.5) };
        let h = len * (1.0 - dip * dip).sqrt();
        let mut p = [x + h * azimuth.cos(), y + h * azimuth.sin(), z + len * dip];
        if self.grid {
            p = p.map(|c| self.round(c));
            if p == self.nodes[from] {
                p[2] += 0.5;
            }
        }
        p
    }

    fn add(&mut self, p: [f64; 3]) -> usize {
        self.nodes.push(p);
        self.nodes.len() - 1
    }

    /// A chain of `len` new nodes from `a` to `b` (a direct link if `len == 0`).
    fn chain(&mut self, a: usize, b: usize, len: usize) {
        let (pa, pb) = (self.nodes[a], self.nodes[b]);
        let mut prev = a;
        for k in 1..=len {
            let t = k as f64 / (len + 1) as f64;
            let wobble = if a == b { 8.0 } else { 3.0 };
            let noise: [f64; 3] = std::array::from_fn(|_| wobble * (self.rng.unit() - 0.5));
            let p: [f64; 3] = std::array::from_fn(|c| self.round(pa[c] + t * (pb[c] - pa[c]) + noise[c]));
            let next = self.add(p);
            self.links.push([prev, next]);
            prev = next;
        }
        self.links.push([prev, b]);
    }

    /// A regular polygon far from everything: all its edges have the same length.
    fn isolated_cycle(&mut self, m: usize) {
        let first = self.nodes.len();
        for k in 0..m {
            let a = std::f64::consts::TAU * k as f64 / m as f64;
            self.add([5e3 + 20.0 * a.cos(), 5e3 + 20.0 * a.sin(), 0.0]);
        }
        for k in 0..m {
            self.links.push([first + k, first + (k + 1) % m]);
        }
    }

    /// A small random tree far from everything (no loop, so no cut positions).
    fn small_tree(&mut self, n: usize) {
        let first = self.add([-5e3, -5e3, 0.0]);
        for i in 1..n {
            let parent = first + self.rng.below(i);
            let child = self.grow(parent);
            self.links.push([parent, child]);
        }
    }
}

/// Writes a network as karstnet's `{base}_nodes.dat` / `{base}_links.dat` (1-based links).
pub fn write_karstnet(net: &Network, base: &Path) {
    let mut nodes = String::new();
    for [x, y, z] in &net.nodes {
        writeln!(nodes, "{x:?} {y:?} {z:?}").expect("string write");
    }
    let mut links = String::new();
    for [a, b] in &net.links {
        writeln!(links, "{} {}", a + 1, b + 1).expect("string write");
    }
    std::fs::write(format!("{}_nodes.dat", base.display()), nodes).expect("write nodes");
    std::fs::write(format!("{}_links.dat", base.display()), links).expect("write links");
}

/// The Python of `KARSTNET_PYTHON` (set by `cargo xtask test`); panics when unset, so that the
/// comparisons with karstnet never pass silently.
pub fn python() -> String {
    std::env::var("KARSTNET_PYTHON").unwrap_or_else(|_| {
        panic!("set KARSTNET_PYTHON to a python with karstnet==1.2.5 (cargo xtask test does this)")
    })
}

/// karstnet 1.2.5's metrics of `base` (`_nodes.dat`/`_links.dat` or a `.pl`), through
/// `karstnet_oracle.py`; panics loudly when the interpreter or karstnet is broken.
pub fn karstnet_metrics(python: &str, base: &Path) -> serde_json::Value {
    let script = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/karstnet_oracle.py");
    let out = std::process::Command::new(python)
        .arg(&script)
        .arg(base)
        .output()
        .unwrap_or_else(|e| panic!("cannot run the karstnet oracle with {python}: {e}"));
    assert!(
        out.status.success(),
        "karstnet oracle failed on {}:\n{}",
        base.display(),
        String::from_utf8_lossy(&out.stderr)
    );
    serde_json::from_slice(&out.stdout).expect("oracle prints JSON")
}
