//! The fuzz targets in the test suite: a fixed number of cases each, from a fixed seed (the
//! same cases every run), and every regression case of `fixtures/bad/fuzz/` replayed.
//! `cargo xtask fuzz --minutes N` runs the same targets for longer, with new seeds.

use karst_fuzz::{replay, run, targets};
use karst_testkit::root;

/// Cases per target: a few thousand in all, a minute or so of the suite.
const CASES: u32 = 1000;

fn fuzz(name: &str) {
    let target = targets().into_iter().find(|t| t.name == name).expect("a target of that name");
    if let Err(failure) = run(&target, CASES, 0) {
        let saved = karst_fuzz::save(&root(), &failure).expect("the fixtures are writable");
        panic!("{failure}: the input is saved as {}; fix the reader, keep the file", saved.display());
    }
}

macro_rules! fuzz_tests {
    ($($test:ident: $name:literal,)*) => {
        $(#[test]
        fn $test() {
            fuzz($name);
        })*
    };
}

fuzz_tests! {
    scene: "scene",
    samples: "samples",
    costgraph: "costgraph",
    skeleton: "skeleton",
    hydro: "hydro",
    sdf: "sdf",
    mesh: "mesh",
    metrics: "metrics",
    manifest: "manifest",
    network_out: "network-out",
    view_mesh: "view-mesh",
    ensemble_grid: "ensemble-grid",
    karstnet: "karstnet",
    pline: "pline",
    csv: "csv",
    tsurf: "tsurf",
    tin: "tin",
    png: "png",
}

#[test]
fn every_regression_case_is_replayed() {
    for target in targets() {
        replay(&root(), &target).unwrap_or_else(|e| panic!("{}: {e}", target.name));
    }
}
