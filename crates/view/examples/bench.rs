//! The viewer's budgets (BENCHMARKS.md): writes RUN/view, serves it on loopback and opens it
//! RUNS times in headless Chromium (`tests/browser.mjs bench`), printing the time to write the
//! view, the median time to interactive (the page's clock, from navigation start to the first
//! frame with every chunk at its coarsest level), the median time until every chunk in view
//! has its level, and the bytes transferred.
//!
//! ```sh
//! cargo run --release -p karst-view --example bench -- out/looping --scene fixtures/scenes/looping.toml \
//!     [--runs 5] [--png docs/images/viewer-looping.png]
//! ```
//!
//! Needs Debian's chromium and tools/node/node_modules (`cargo xtask test` installs both).

use std::path::{Path, PathBuf};
use std::process::{Command, ExitCode};
use std::time::Instant;

use karst_view::{Server, write_view};

struct Args {
    run: PathBuf,
    scene: Option<PathBuf>,
    png: Option<PathBuf>,
    runs: usize,
}

fn parse() -> Result<Args, String> {
    let mut args = std::env::args().skip(1);
    let mut parsed = Args { run: PathBuf::new(), scene: None, png: None, runs: 5 };
    while let Some(arg) = args.next() {
        let mut value = || args.next().ok_or(format!("{arg} needs a value"));
        match arg.as_str() {
            "--scene" => parsed.scene = Some(value()?.into()),
            "--png" => parsed.png = Some(value()?.into()),
            "--runs" => parsed.runs = value()?.parse().map_err(|e| format!("--runs: {e}"))?,
            _ if parsed.run.as_os_str().is_empty() => parsed.run = arg.into(),
            _ => return Err(format!("unexpected argument {arg}")),
        }
    }
    if parsed.run.as_os_str().is_empty() || parsed.runs == 0 {
        return Err("usage: bench RUN_DIR [--scene SCENE] [--runs N] [--png FILE]".into());
    }
    Ok(parsed)
}

fn main() -> ExitCode {
    match parse().and_then(|args| bench(&args)) {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("error: {e}");
            ExitCode::from(1)
        }
    }
}

fn bench(args: &Args) -> Result<(), String> {
    let start = Instant::now();
    let report = write_view(&args.run, args.scene.as_deref()).map_err(|e| e.to_string())?;
    println!("wrote {} in {:.2} s", report.headline(), start.elapsed().as_secs_f64());
    let server = Server::bind(&report.dir, 0).map_err(|e| e.to_string())?;
    let url = server.url();
    std::thread::spawn(move || server.run());
    let mut runs: Vec<serde_json::Value> = Vec::new();
    for k in 0..args.runs {
        let png = if k + 1 == args.runs { args.png.as_deref() } else { None };
        let result = open(&url, png)?;
        println!("{result}");
        runs.push(result);
    }
    let median = |key: &str| {
        let mut v: Vec<f64> = runs.iter().filter_map(|r| r[key].as_f64()).collect();
        v.sort_by(f64::total_cmp);
        v[v.len() / 2]
    };
    println!(
        "median of {}: interactive {:.2} s, settled {:.2} s, {:.1} MB in {} requests",
        runs.len(),
        median("interactive"),
        median("settled"),
        median("megabytes"),
        median("requests")
    );
    Ok(())
}

fn open(url: &str, png: Option<&Path>) -> Result<serde_json::Value, String> {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let modules = std::env::var_os("KARSTGEN_NODE_MODULES")
        .map(PathBuf::from)
        .unwrap_or_else(|| root.join("../../tools/node/node_modules"));
    let mut command = Command::new("node");
    command.arg(root.join("tests/browser.mjs")).args(["bench", url]).env("KARSTGEN_NODE_MODULES", modules);
    if let Some(png) = png {
        command.arg(png);
    }
    let output = command.output().map_err(|e| format!("node: {e}"))?;
    if !output.status.success() {
        return Err(format!("browser.mjs bench: {}", String::from_utf8_lossy(&output.stderr)));
    }
    serde_json::from_slice(&output.stdout).map_err(|e| format!("browser.mjs bench printed no JSON: {e}"))
}
