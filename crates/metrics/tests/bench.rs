//! Timings (printed, not asserted): `cargo test --release -p karst-metrics --test bench --
//! --ignored --nocapture`. With `KARSTNET_PYTHON` set, karstnet's time on the same files is printed
//! too (the Python time includes interpreter start-up and imports, ~1.5 s).

mod common;

use std::time::{Duration, Instant};

use common::{CaveSpec, caves_dir, random_cave, temp_dir, write_karstnet};
use karst_metrics::readers::read_karstnet;
use karst_metrics::{Network, characterize};

fn best_of(runs: usize, net: &Network) -> Duration {
    (0..runs)
        .map(|_| {
            let start = Instant::now();
            characterize(net).expect("valid");
            start.elapsed()
        })
        .min()
        .unwrap_or_default()
}

fn karstnet_time(base: &std::path::Path) -> Option<Duration> {
    let python = std::env::var("KARSTNET_PYTHON").ok()?;
    let script = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/karstnet_oracle.py");
    let start = Instant::now();
    let status = std::process::Command::new(python).arg(script).arg(base).output().ok()?.status;
    status.success().then(|| start.elapsed())
}

fn report(name: &str, net: &Network, base: &std::path::Path) {
    let m = characterize(net).expect("valid");
    let ours = best_of(10, net);
    let theirs = karstnet_time(base).map_or("(set KARSTNET_PYTHON)".into(), |d| format!("{d:.2?}"));
    println!(
        "{name}: {} nodes, {} reduced nodes: karst-metrics {ours:.2?}, karstnet {theirs}",
        m.n_nodes_full, m.n_nodes_simpl
    );
}

#[test]
#[ignore = "timing report, run explicitly"]
fn timings() {
    let sakany = caves_dir().join("Sakany");
    report("Sakany", &read_karstnet(&sakany).expect("Sakany"), &sakany);
    let dir = temp_dir("bench");
    for (name, tree_nodes) in [("random-7k", 6_300), ("random-10k", 9_000)] {
        let spec = CaveSpec {
            tree_nodes,
            chain_bias: 0.9,
            loops: tree_nodes / 25,
            parallel_pairs: 20,
            looping_branches: 10,
            grid: false,
            extra_components: true,
        };
        let net = random_cave(7, spec);
        let base = dir.join(name);
        write_karstnet(&net, &base);
        report(name, &net, &base);
    }
    std::fs::remove_dir_all(dir).expect("remove temp dir");
}
