//! Timing of the surface network and its classification on the default scene and the waterfall
//! preset (`cargo test --release -p karst-streams --test bench -- --ignored --nocapture`);
//! budget 50 ms on the default scene, results in BENCHMARKS.md. Never asserts a time.

use std::path::Path;
use std::time::Instant;

use karst_artifact::cli::RunArgs;
use karst_artifact::read_artifact;
use karst_geology::Scene;
use karst_hydro::Hydro;

#[test]
#[ignore]
fn time_the_surface_network() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("../..");
    for name in ["default", "waterfall"] {
        let scene_path = root.join(format!("fixtures/scenes/{name}.toml"));
        let out = std::env::temp_dir().join(format!("karst-streams-bench-{name}-{}", std::process::id()));
        let args = RunArgs { scene: scene_path.clone(), out: out.clone() };
        karst_sampling::stage::run(&args).unwrap();
        karst_costgraph::stage::run(&args).unwrap();
        karst_skeleton::stage::run(&args).unwrap();
        karst_hydro::stage::run(&args).unwrap();
        let scene = Scene::load(&scene_path).unwrap();
        let (_, hydro): (_, Hydro) = read_artifact(&out.join("hydro.json")).unwrap();
        let _ = std::fs::remove_dir_all(&out);
        let mut times = Vec::new();
        let mut headline = String::new();
        for _ in 0..11 {
            let start = Instant::now();
            let streams = karst_streams::build(&scene, &hydro).unwrap();
            times.push(start.elapsed().as_secs_f64());
            headline = streams.headline();
        }
        times.sort_by(f64::total_cmp);
        println!("{name}: median {:.1} ms (min {:.1}) — {headline}", times[5] * 1e3, times[0] * 1e3);
    }
}
