//! `cargo xtask bench --calibrate`: the calibration budgets of issues 20 and 38: the default
//! scene's `[calibrate]` box against the fixtures' Sakany cave (`--target`), the median of the
//! surveyed caves and two published surveyed caves (`--like`). Each runs `karstgen calibrate`
//! in process, once; then the scene and the calibrated scene each run on three fresh seeds (not
//! the seeds searched) and their median distance to the target is compared: the honest measure
//! of a calibration, which its own objective overstates by fitting its seeds.

use std::path::Path;
use std::time::Instant;

use karst_metrics::aim;
use karst_pipeline::calibrate::{Aim, CalibrateArgs, Runner, run};
use karst_pipeline::scene::SceneFile;
use karst_stage::StageError;

use super::probes;

const SCENE: &str = "fixtures/scenes/default.toml";
/// The fresh seeds: far from the scene's seed and the next ones, which the search uses.
const FRESH: [u64; 3] = [3001, 3002, 3003];

/// The targets: the fixtures' Sakany survey, the surveyed median and two published caves.
fn aims() -> Vec<(String, Aim)> {
    vec![
        ("fixtures/caves/Sakany_nodes.dat".into(), Aim::Cave(vec!["fixtures/caves/Sakany_nodes.dat".into()])),
        ("--like surveyed".into(), Aim::Like("surveyed".into())),
        ("--like Criou".into(), Aim::Like("Criou".into())),
        ("--like Tsanfleuron".into(), Aim::Like("Tsanfleuron".into())),
    ]
}

/// Runs each calibration into a scratch folder (removed afterwards) and prints its figures.
pub fn calibrate_bench() -> Result<(), StageError> {
    println!(
        "| scene → target | candidates × seeds | search: distance before → after | half reached at | fresh seeds {FRESH:?}: median before → after | wall s | CPU s |"
    );
    println!("|---|---|---|---|---|---|---|");
    for (name, target) in aims() {
        let line = one(&name, target)?;
        println!("{line}");
    }
    Ok(())
}

fn one(name: &str, target: Aim) -> Result<String, StageError> {
    let out = super::scratch_dir(Path::new(SCENE));
    let args = CalibrateArgs { scene: SCENE.into(), target: Some(target.clone()), out: out.to_path_buf() };
    let (cpu0, start) = (probes::cpu_seconds(), Instant::now());
    let summary = run(&args)?;
    let wall = start.elapsed().as_secs_f64();
    let cpu = probes::cpu_seconds().zip(cpu0).map_or("-".into(), |(b, a)| format!("{:.1}", b - a));
    eprintln!("{summary}");
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
    let (fresh_before, fresh_after) = fresh(&target, &out.join("calibrated.toml"))?;
    drop(out);
    Ok(format!(
        "| default scene → {name} | {} × {} | {before:.4} → {:.4} ({:.0} %) | {half} | {fresh_before:.4} → {fresh_after:.4} ({:.0} %) | {wall:.1} | {cpu} |",
        report["candidates"],
        report["seeds"].as_array().map_or(0, Vec::len),
        report["distance"]["after"].as_f64().unwrap_or(f64::NAN),
        -100.0 * report["distance"]["reduction"].as_f64().unwrap_or(f64::NAN),
        100.0 * (fresh_after / fresh_before - 1.0),
    ))
}

/// The median distance to `target` over the fresh seeds of the scene and of the calibrated
/// scene, their networks built as the calibration builds its candidates.
fn fresh(target: &Aim, calibrated: &Path) -> Result<(f64, f64), StageError> {
    let goal = match target {
        Aim::Like(name) => aim::like(name),
        Aim::Cave(files) => aim::cave(files),
    }
    .map_err(|e| StageError::failure(e.to_string()))?;
    let widths = aim::widths();
    let median_distance = |path: &Path| -> Result<f64, StageError> {
        let scene = SceneFile::load(path)?;
        let runner = Runner::new(&scene.scene, FRESH.to_vec(), &[])
            .map_err(|e| StageError::failure(format!("{}: {e}", path.display())))?;
        let runs = runner.run(std::slice::from_ref(&scene.scene), &|| {}).remove(0);
        let distances = runs
            .into_iter()
            .map(|m| m.map(|m| aim::distance(&m, &goal.statistics, &widths)))
            .collect::<Result<Vec<f64>, _>>()
            .map_err(|e| StageError::failure(format!("{}: {e}", path.display())))?;
        eprintln!("{}: fresh distances {distances:?}", path.display());
        Ok(aim::median(distances))
    };
    Ok((median_distance(Path::new(SCENE))?, median_distance(calibrated)?))
}
