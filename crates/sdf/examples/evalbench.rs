//! Times `CarvedTerrain::eval` on an sdf.bin: points uniform in the domain and within 6 m of a
//! skeleton node. `cargo run --release -p karst-sdf --example evalbench -- DIR [RUNS] [uniform|near]`.
//! Times are the process's CPU time (/proc/self/schedstat, nanoseconds); the hash of the
//! values' bits shows whether a change kept every value.
use karst_artifact::read_artifact;
use karst_scene::SceneView;
use karst_sdf::{CarvedTerrain, SdfModel};
use karst_skeleton::Skeleton;

fn main() {
    let args: Vec<String> = std::env::args().collect();
    if args[1] == "micro" {
        micro();
        return;
    }
    let dir = std::path::Path::new(&args[1]);
    let runs: usize = args.get(2).and_then(|r| r.parse().ok()).unwrap_or(5);
    let (model, skeleton): (SdfModel, Skeleton) = if args[1] == "synthetic" {
        let (skeleton, hydro) = karst_sdf::synthetic::network(5, 100, 12);
        {
            let scene = karst_scene::Scene::parse(
                karst_sdf::synthetic::SCENE,
                std::path::Path::new("synthetic.toml"),
            )
            .unwrap();
            (karst_sdf::build(&karst_sdf::SdfView::of(&scene), &skeleton, &hydro).unwrap(), skeleton)
        }
    } else {
        (read_artifact(&dir.join("sdf.bin")).unwrap().1, read_artifact(&dir.join("skeleton.json")).unwrap().1)
    };
    let field = CarvedTerrain::new(model);
    let [uniform, near] = karst_sdf::synthetic::eval_points(&field, &skeleton, 200_000);
    let mut check = 0.0;
    let mut hash = 0xcbf29ce484222325u64;
    let only = args.get(3).map(String::as_str);
    for (name, pts) in [("uniform", &uniform), ("near", &near)] {
        if only.is_some_and(|o| o != name) {
            continue;
        }
        for &p in pts {
            hash = (hash ^ field.eval(p).to_bits()).wrapping_mul(0x100000001b3);
        }
        let mut t: Vec<f64> = (0..runs)
            .map(|_| {
                let c = cpu();
                let sum: f64 = pts.iter().map(|&p| field.eval(p)).sum();
                check += sum;
                (cpu() - c) * 1e9 / pts.len() as f64
            })
            .collect();
        t.sort_by(f64::total_cmp);
        println!(
            "{name:<8} {:>8.1} ns (runs {:?})",
            t[t.len() / 2],
            t.iter().map(|x| (x * 10.0).round() / 10.0).collect::<Vec<_>>()
        );
    }
    let [k, w] = field.memory();
    let n = field.leaves();
    println!(
        "leaves {n}, memory karst {k} ({:.1} B/leaf), water {w}, total {:.1} B/leaf",
        k as f64 / n as f64,
        (k + w) as f64 / n as f64
    );
    println!("checksum {check:.6e}, hash of the values {hash:016x}");
}

/// CPU seconds of this (single-threaded) process: the scheduler's run time, in nanoseconds.
fn cpu() -> f64 {
    let stat = std::fs::read_to_string("/proc/self/schedstat").unwrap();
    stat.split_whitespace().next().unwrap().parse::<f64>().unwrap() * 1e-9
}

#[allow(dead_code)]
pub fn micro() {
    use karst_sdf::{Section, Shape};
    let s = Section::blend(
        [karst_skeleton::ConduitType::Keyhole, karst_skeleton::ConduitType::Canyon],
        Shape { radius: 2.0, ratio: 1.0, asymmetry: 0.2 },
    );
    let mut x = 0.0;
    let c = cpu();
    let n = 2_000_000;
    for i in 0..n {
        let q = glam::DVec2::new((i % 1000) as f64 * 0.006 - 3.0, (i / 1000 % 1000) as f64 * 0.006 - 3.0);
        x += s.distance(q);
    }
    println!("Section::distance {:.1} ns ({x})", (cpu() - c) * 1e9 / n as f64);
}
