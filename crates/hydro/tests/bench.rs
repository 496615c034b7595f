//! Timing of the hydro computation on large mazes (`cargo test --release -p karst-hydro --test
//! bench -- --ignored --nocapture`); results in BENCHMARKS.md. Never asserts a time.

use std::time::Instant;

use karst_hydro::{Inputs, compute};
use karst_scene::params::HydroParams;
use karst_scene::rng::Random;
use karst_skeleton::{Conduit, ConduitType, Node, Route, Skeleton, Zone};

/// An n × n grid maze on a slope with noisy elevations (every cell a loop), `sinks` sinks
/// on the high side and two springs on the low side; the lowest third is phreatic.
fn maze(n: usize, sinks: usize) -> Skeleton {
    let mut rng = Random::stream(1, "hydro-bench", "maze");
    let nodes: Vec<Node> = (0..n * n)
        .map(|i| {
            let (x, y) = ((i % n) as f64 * 10.0, (i / n) as f64 * 10.0);
            let z = 300.0 - x * 0.2 + rng.range(-3.0, 3.0);
            let zone = if x > n as f64 * 10.0 * 2.0 / 3.0 { Zone::Phreatic } else { Zone::Vadose };
            Node { position: [x, y, z], sample: i as u32, keypoint: None, zone }
        })
        .collect();
    let mut conduits = Vec::new();
    for i in 0..n * n {
        let (col, row) = (i % n, i / n);
        for j in [(col + 1 < n).then(|| i + 1), (row + 1 < n).then(|| i + n)].into_iter().flatten() {
            conduits.push(Conduit {
                nodes: vec![i as u32, j as u32],
                radius: vec![2.0; 2],
                types: vec![ConduitType::Canyon],
                phase: 0,
                keypoints: vec![],
                profile: Vec::new(),
            });
        }
    }
    let springs = [(n / 3) * n + n - 1, (2 * n / 3) * n + n - 1];
    let routes = (0..sinks)
        .map(|s| Route {
            sink: format!("sink-{s}"),
            spring: format!("spring-{}", s % 2),
            weight: 1.0 + s as f64,
            nodes: vec![(rng.index(n) * n) as u32, springs[s % 2] as u32],
            cost: 0.0,
        })
        .collect();
    Skeleton { nodes, conduits, routes, derived: Default::default() }
}

#[test]
#[ignore]
fn time_mazes() {
    for (n, sinks) in [(50, 5), (100, 20), (200, 20)] {
        let skeleton = maze(n, sinks);
        let mut times = Vec::new();
        for _ in 0..5 {
            let start = Instant::now();
            compute(&skeleton, &HydroParams::default(), &Inputs::default()).unwrap();
            times.push(start.elapsed().as_secs_f64());
        }
        times.sort_by(f64::total_cmp);
        println!("maze {n}×{n} ({} links), {sinks} sinks: median {:.4} s", skeleton.links().len(), times[2]);
    }
}
