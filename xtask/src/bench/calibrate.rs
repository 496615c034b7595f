//! `cargo xtask bench --calibrate`: the calibration budget of issue 20: the default scene's
//! `[calibrate]` box against the fixtures' Sakany cave; the distance must fall by half within
//! 10 minutes on the 2-core machine. Runs `karstgen calibrate` in process, once, and reports the
//! wall and CPU time of the whole budget and the first candidate at half the initial distance.

use std::path::Path;
use std::time::Instant;

use karst_pipeline::calibrate::{Aim, CalibrateArgs, run};
use karst_stage::StageError;

use super::probes;

const SCENE: &str = "fixtures/scenes/default.toml";
const TARGET: &str = "fixtures/caves/Sakany_nodes.dat";

/// Runs the calibration into a scratch folder (removed afterwards) and prints its figures.
pub fn calibrate_bench() -> Result<(), StageError> {
    let out = super::scratch_dir(Path::new(SCENE));
    let args =
        CalibrateArgs { scene: SCENE.into(), target: Aim::Cave(vec![TARGET.into()]), out: out.to_path_buf() };
    let (cpu0, start) = (probes::cpu_seconds(), Instant::now());
    let summary = run(&args)?;
    let wall = start.elapsed().as_secs_f64();
    let cpu = probes::cpu_seconds().zip(cpu0).map_or("-".into(), |(b, a)| format!("{:.1}", b - a));
    let read = |f: &str| {
        std::fs::read_to_string(out.join(f))
            .map_err(|e| StageError::failure(format!("{}: {e}", out.join(f).display())))
    };
    let report: serde_json::Value =
        serde_json::from_str(&read("report.json")?).map_err(|e| StageError::failure(e.to_string()))?;
    let before = report["distance"]["before"].as_f64().unwrap_or(f64::NAN);
    let half = read("iterations.csv")?
        .lines()
        .skip(1)
        .position(|row| {
            row.split(',').nth(3).and_then(|d| d.parse::<f64>().ok()).is_some_and(|d| d <= before / 2.0)
        })
        .map_or("never".into(), |i| format!("candidate {}", i + 1));
    drop(out);
    println!("{summary}");
    println!(
        "| scene | target | candidates × seeds | distance before → after | half reached at | wall s | CPU s |"
    );
    println!("|---|---|---|---|---|---|---|");
    println!(
        "| {SCENE} | {TARGET} | {} × {} | {before:.4} → {:.4} ({:.0} % less) | {half} | {wall:.1} | {cpu} |",
        report["candidates"],
        report["seeds"].as_array().map_or(0, Vec::len),
        report["distance"]["after"].as_f64().unwrap_or(f64::NAN),
        100.0 * report["distance"]["reduction"].as_f64().unwrap_or(f64::NAN),
    );
    Ok(())
}
