//! `cargo xtask bench --regional`: every stage on the regional scene (issue 21), as whole
//! processes, with each stage's wall time, CPU time and peak resident memory.
//!
//! The scene, `fixtures/bench/regional.toml`, is a 10 × 10 × 1 km massif of about 5 M
//! samples. The network half (sampling, cost graph, skeleton) runs first on the same scene
//! at a coarser radius ([`SMALL_RADIUS`], about 1 M samples), then every stage but the export
//! runs at the scene's own radius; the growth exponent of each network stage between the two
//! sizes, ln(CPU ratio) / ln(sample ratio), says how close to linear it scales. Artifacts go
//! to a temporary folder, removed at the end (the full run writes about 6 GB).

use std::path::{Path, PathBuf};
use std::process::Command;

use karst_artifact::StageId;
use karst_stage::StageError;

use crate::temp_folder::TempFolder;

use crate::peer::{self, Usage};

/// The scene.
pub const SCENE: &str = "fixtures/bench/regional.toml";
/// `sampling.radius` of the smaller run, metres: about 1.04 M samples.
const SMALL_RADIUS: f64 = 36.8;
/// The stages of the network half, measured at both sizes.
const NETWORK_HALF: [StageId; 3] = [StageId::Sampling, StageId::Costgraph, StageId::Skeleton];

/// One stage's run.
pub struct StageRun {
    pub stage: StageId,
    pub usage: Usage,
    /// The stage's one-line report (its stdout).
    pub report: String,
}

/// The runs of one scene size.
pub struct SizeRun {
    pub samples: usize,
    pub stages: Vec<StageRun>,
}

impl SizeRun {
    /// The summed usage of the network half (the peak is the largest stage's).
    pub fn network_half(&self) -> Usage {
        self.stages
            .iter()
            .filter(|r| NETWORK_HALF.contains(&r.stage))
            .fold(Usage::default(), |total, r| total.then(r.usage))
    }

    fn usage(&self, stage: StageId) -> Option<Usage> {
        self.stages.iter().find(|r| r.stage == stage).map(|r| r.usage)
    }
}

/// Runs the network half at the small size, then at the scene's size the network half or, with
/// `full`, every stage but the export; `bin` holds the stage binaries.
pub fn run(bin: &Path, full: bool) -> Result<(SizeRun, SizeRun), StageError> {
    run_in(&TempFolder::new("regional"), bin, full)
}

fn run_in(scratch: &Path, bin: &Path, full: bool) -> Result<(SizeRun, SizeRun), StageError> {
    let small_scene = scratch.join("regional-1m.toml");
    let radius = [("sampling", "radius", toml::Value::Float(SMALL_RADIUS))];
    peer::write_edited_scene(Path::new(SCENE), &small_scene, &radius)?;
    let small = run_stages(&small_scene, &scratch.join("1m"), bin, &NETWORK_HALF)?;
    let _ = std::fs::remove_dir_all(scratch.join("1m"));
    let stages: Vec<StageId> = if full {
        StageId::ALL.into_iter().filter(|&s| s != StageId::Export).collect()
    } else {
        NETWORK_HALF.to_vec()
    };
    let large = run_stages(Path::new(SCENE), &scratch.join("5m"), bin, &stages)?;
    Ok((small, large))
}

/// Runs `stages` in order on `scene` into `out`, each as its own process.
fn run_stages(scene: &Path, out: &Path, bin: &Path, stages: &[StageId]) -> Result<SizeRun, StageError> {
    let _ = std::fs::remove_dir_all(out);
    std::fs::create_dir_all(out).map_err(|e| StageError::failure(format!("{}: {e}", out.display())))?;
    let mut run = SizeRun { samples: 0, stages: Vec::new() };
    for &stage in stages {
        let mut command = Command::new(bin.join(stage.row().binary));
        command.arg("run").arg(scene).arg("--out").arg(out);
        let log = out.join(format!("{}.log", stage.name()));
        let (usage, report) = peer::measure(command, &log)?;
        let report = report.lines().last().unwrap_or_default().to_string();
        eprintln!(
            "{}: {:.1} s wall, {:.1} s CPU, {:.0} MB: {report}",
            stage.name(),
            usage.wall,
            usage.cpu,
            mb(usage)
        );
        if stage == StageId::Sampling {
            run.samples = peer::first_number(&report)
                .ok_or_else(|| StageError::failure(format!("sampling said {report:?}")))?;
        }
        run.stages.push(StageRun { stage, usage, report });
    }
    Ok(run)
}

fn mb(usage: Usage) -> f64 {
    usage.peak_bytes as f64 / 1e6
}

/// The table of both sizes, with each network stage's growth exponent.
pub fn table(small: &SizeRun, large: &SizeRun) -> String {
    let mut out = format!(
        "| stage | {} samples: wall / CPU / peak | {} samples: wall / CPU / peak | exponent (CPU) |\n|---|---|---|---|\n",
        small.samples, large.samples
    );
    let ratio = large.samples as f64 / small.samples.max(1) as f64;
    let exponent = |a: Usage, b: Usage| format!("{:.2}", (b.cpu / a.cpu).ln() / ratio.ln());
    let show = |u: Option<Usage>| {
        u.map_or("–".to_string(), |u| format!("{:.1} s / {:.1} s / {:.0} MB", u.wall, u.cpu, mb(u)))
    };
    for run in &large.stages {
        let before = small.usage(run.stage);
        let growth = before.map_or("–".to_string(), |b| exponent(b, run.usage));
        out +=
            &format!("| {} | {} | {} | {growth} |\n", run.stage.name(), show(before), show(Some(run.usage)));
    }
    let (a, b) = (small.network_half(), large.network_half());
    out += &format!("| network half | {} | {} | {} |\n", show(Some(a)), show(Some(b)), exponent(a, b));
    out
}

/// The stage binaries' folder after building every stage but the export (release).
pub fn binaries() -> Result<PathBuf, StageError> {
    let stages: Vec<StageId> = StageId::ALL.into_iter().filter(|&s| s != StageId::Export).collect();
    peer::build_stage_binaries(&stages)
}
