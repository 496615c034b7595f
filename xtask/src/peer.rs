//! `cargo xtask bench --peer`: karstgen's network half beside KarstNSim (issue 21).
//!
//! Both sides run as whole processes on one scene, `fixtures/bench/karstnsim-peer.toml`:
//! karstgen as a user runs it, `karstgen run SCENE --to skeleton` (the sampling, cost graph and
//! skeleton stages in one process, every artifact written and synced), KarstNSim as
//! PyPI `pykarstnsim` (its C++ core, single-threaded) driven by `tools/peer/pykarstnsim_run.py`,
//! installed into `.venv-peer` from `tools/peer/requirements.txt`. The runs alternate (ours,
//! theirs, ours, ...) so that a change of the machine's load hits both sides alike. Each child
//! is reaped with `wait4`, which gives its own CPU time and peak resident memory.
//!
//! Each case fixes both sampling radii so that the two sample counts agree within 2 % (checked
//! on every run) and gives both the same k.

use std::fs::File;
use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};
use std::time::Instant;

use karst_artifact::StageId;
use karst_stage::StageError;

use crate::temp_folder::TempFolder;

/// The scene both sides run.
pub const SCENE: &str = "fixtures/bench/karstnsim-peer.toml";
const REQUIREMENTS: &str = "tools/peer/requirements.txt";
const VENV: &str = ".venv-peer";
const DRIVER: &str = "tools/peer/pykarstnsim_run.py";
/// The largest relative difference of the two sample counts.
const COUNT_TOLERANCE: f64 = 0.02;

/// One side-by-side case.
pub struct PeerCase {
    pub name: &'static str,
    /// karstgen's `sampling.radius`, metres.
    pub radius: f64,
    /// KarstNSim's `poisson_radius`, a fraction of the domain's smallest extent (600 m).
    pub peer_radius: f64,
    pub k: usize,
    /// `RAYON_NUM_THREADS` for karstgen (None: all cores). KarstNSim is single-threaded.
    pub threads: Option<usize>,
}

/// The cases of issue 21.
pub const CASES: &[PeerCase] = &[
    PeerCase { name: "100k, k = 50", radius: 14.2, peer_radius: 0.02245, k: 50, threads: None },
    PeerCase { name: "300k, k = 50", radius: 9.86, peer_radius: 0.01563, k: 50, threads: None },
    PeerCase { name: "1M, k = 30", radius: 6.6, peer_radius: 0.01044, k: 30, threads: None },
    PeerCase { name: "100k, k = 50, 1 thread", radius: 14.2, peer_radius: 0.02245, k: 50, threads: Some(1) },
];

/// What one process (or one side's chain of processes) used.
#[derive(Debug, Clone, Copy, Default)]
pub struct Usage {
    pub wall: f64,
    /// User + system seconds of the process and its threads.
    pub cpu: f64,
    /// Peak resident memory, bytes (the largest of a chain's processes).
    pub peak_bytes: u64,
}

impl Usage {
    /// The usage of two processes run one after the other.
    pub fn then(self, next: Usage) -> Usage {
        Usage {
            wall: self.wall + next.wall,
            cpu: self.cpu + next.cpu,
            peak_bytes: self.peak_bytes.max(next.peak_bytes),
        }
    }
}

/// One case's measurements: every run of each side, and the sample counts.
pub struct PeerResult {
    pub ours: Vec<Usage>,
    pub theirs: Vec<Usage>,
    pub our_samples: usize,
    pub their_samples: usize,
}

impl PeerResult {
    /// The median of each figure over the runs, per side.
    pub fn medians(&self) -> (Usage, Usage) {
        (median_usage(&self.ours), median_usage(&self.theirs))
    }
}

fn median_usage(runs: &[Usage]) -> Usage {
    let median = |f: &dyn Fn(&Usage) -> f64| {
        let mut v: Vec<f64> = runs.iter().map(f).collect();
        v.sort_by(f64::total_cmp);
        v[v.len() / 2]
    };
    Usage {
        wall: median(&|u| u.wall),
        cpu: median(&|u| u.cpu),
        peak_bytes: median(&|u| u.peak_bytes as f64) as u64,
    }
}

/// Builds karstgen (release) and returns its path, beside this xtask binary.
pub fn karstgen_binary() -> Result<PathBuf, StageError> {
    build_release(&["--package", "karstgen"], "karstgen")?;
    Ok(beside_xtask()?.join("karstgen"))
}

/// Builds the binaries of `stages` (release) and returns their folder, beside this xtask binary.
pub fn build_stage_binaries(stages: &[StageId]) -> Result<PathBuf, StageError> {
    let packages: Vec<&str> = stages.iter().flat_map(|s| ["--package", s.row().binary]).collect();
    build_release(&packages, "the stage binaries")?;
    beside_xtask()
}

/// `cargo build --release --quiet --bins` with `args`; `what` names what it builds in errors.
fn build_release(args: &[&str], what: &str) -> Result<(), StageError> {
    let cargo = std::env::var_os("CARGO").unwrap_or_else(|| "cargo".into());
    let status = Command::new(cargo)
        .args(["build", "--release", "--quiet", "--bins"])
        .args(args)
        .status()
        .map_err(|e| StageError::failure(format!("cannot run cargo: {e}")))?;
    if !status.success() {
        return Err(StageError::failure(format!("building {what} failed")));
    }
    Ok(())
}

/// The folder of this xtask binary, where cargo puts the release binaries.
fn beside_xtask() -> Result<PathBuf, StageError> {
    let exe = std::env::current_exe().map_err(StageError::failure)?;
    let dir = exe.parent().ok_or_else(|| StageError::failure("the xtask binary has no folder"))?;
    Ok(dir.to_path_buf())
}

/// Installs the peer when missing and returns its Python.
pub fn peer_python(root: &Path) -> Result<PathBuf, StageError> {
    crate::tools::ensure_venv(root, REQUIREMENTS, VENV).map_err(StageError::failure)
}

/// Runs `case` `runs` times on each side, alternately; `karstgen` is our binary.
pub fn run_case(
    case: &PeerCase,
    runs: usize,
    karstgen: &Path,
    python: &Path,
) -> Result<PeerResult, StageError> {
    let scratch = TempFolder::new("peer");
    let scene = scratch.join("scene.toml");
    write_scene(case, &scene)?;
    let mut result = PeerResult { ours: Vec::new(), theirs: Vec::new(), our_samples: 0, their_samples: 0 };
    for _ in 0..runs.max(1) {
        let (usage, samples) = run_ours(case, &scene, &scratch.join("ours"), karstgen)?;
        result.ours.push(usage);
        result.our_samples = samples;
        let (usage, samples) = run_theirs(case, python, &scratch.join("theirs"))?;
        result.theirs.push(usage);
        result.their_samples = samples;
        let gap = (result.our_samples as f64 / result.their_samples.max(1) as f64 - 1.0).abs();
        if gap > COUNT_TOLERANCE {
            return Err(StageError::failure(format!(
                "{}: karstgen sampled {} points, KarstNSim {}: more than {:.0} % apart; recalibrate the case's radii",
                case.name,
                result.our_samples,
                result.their_samples,
                COUNT_TOLERANCE * 100.0
            )));
        }
    }
    Ok(result)
}

/// The peer scene with the case's radius and k.
fn write_scene(case: &PeerCase, path: &Path) -> Result<(), StageError> {
    let edits = [
        ("sampling", "radius", toml::Value::Float(case.radius)),
        ("costgraph", "k", toml::Value::Integer(case.k as i64)),
    ];
    write_edited_scene(Path::new(SCENE), path, &edits)
}

/// Writes `source`'s scene to `path` with each (section, key, value) of `edits` set.
pub(crate) fn write_edited_scene(
    source: &Path,
    path: &Path,
    edits: &[(&str, &str, toml::Value)],
) -> Result<(), StageError> {
    let fail = |p: &Path, e: String| StageError::failure(format!("{}: {e}", p.display()));
    let text = std::fs::read_to_string(source).map_err(|e| fail(source, e.to_string()))?;
    let mut scene: toml::Table = text.parse().map_err(|e: toml::de::Error| fail(source, e.to_string()))?;
    for (name, key, value) in edits {
        let Some(toml::Value::Table(section)) = scene.get_mut(*name) else {
            return Err(fail(source, format!("no [{name}] section")));
        };
        section.insert((*key).into(), value.clone());
    }
    std::fs::create_dir_all(path.parent().unwrap_or(Path::new(".")))
        .map_err(|e| fail(path, e.to_string()))?;
    std::fs::write(path, scene.to_string()).map_err(|e| fail(path, e.to_string()))
}

/// karstgen's network half, the stages KarstNSim's run covers, as a user runs it: one
/// `karstgen run SCENE --to skeleton` from an empty folder (the sampling, cost graph and
/// skeleton stages; every artifact written, the payloads handed from stage to stage).
fn run_ours(
    case: &PeerCase,
    scene: &Path,
    out: &Path,
    karstgen: &Path,
) -> Result<(Usage, usize), StageError> {
    let _ = std::fs::remove_dir_all(out);
    let mut command = Command::new(karstgen);
    command.arg("run").arg(scene).arg("--out").arg(out).args(["--to", StageId::Skeleton.name()]);
    if let Some(threads) = case.threads {
        command.env("RAYON_NUM_THREADS", threads.to_string());
    }
    let (usage, report) = measure(command, &out.with_extension("log"))?;
    let samples =
        sample_count(&report).ok_or_else(|| StageError::failure(format!("karstgen run said {report:?}")))?;
    Ok((usage, samples))
}

/// The sample count in `karstgen run`'s report: the first figure of the sampling stage's line
/// ("sampling   ran   0.15 s  100234 samples, …").
fn sample_count(report: &str) -> Option<usize> {
    let line = report.lines().find(|l| l.starts_with(StageId::Sampling.name()))?;
    let (_, figures) = line.split_once(" s ")?;
    first_number(figures)
}

/// KarstNSim on the same scene.
fn run_theirs(case: &PeerCase, python: &Path, out: &Path) -> Result<(Usage, usize), StageError> {
    let _ = std::fs::remove_dir_all(out);
    let mut command = Command::new(python);
    command
        .arg(DRIVER)
        .arg(SCENE)
        .args(["--poisson-radius", &case.peer_radius.to_string(), "--k", &case.k.to_string(), "--out"])
        .arg(out);
    let (usage, stdout) = measure(command, &out.with_extension("log"))?;
    let samples = stdout
        .split_whitespace()
        .skip_while(|w| *w != "samples")
        .nth(1)
        .and_then(|n| n.parse().ok())
        .ok_or_else(|| StageError::failure(format!("{DRIVER} said {stdout:?}")))?;
    Ok((usage, samples))
}

/// The first word of a stage's report as a number (the sampling stage reports its sample count).
pub(crate) fn first_number(text: &str) -> Option<usize> {
    text.split_whitespace().next()?.parse().ok()
}

/// Runs `command` to its end with its stdout in `log`; its wall time, its own CPU time and peak
/// resident memory (from `wait4`), and its stdout. A failing command is an error quoting its
/// output.
pub(crate) fn measure(mut command: Command, log: &Path) -> Result<(Usage, String), StageError> {
    let program = command.get_program().to_string_lossy().into_owned();
    let fail = |e: String| StageError::failure(format!("{program}: {e}"));
    let file = File::create(log).map_err(|e| fail(format!("{}: {e}", log.display())))?;
    let errors = file.try_clone().map_err(|e| fail(e.to_string()))?;
    command.stdout(Stdio::from(file)).stderr(Stdio::from(errors));
    let start = Instant::now();
    let child = command.spawn().map_err(|e| fail(e.to_string()))?;
    let (status, usage) = reap(child.id() as libc::pid_t).map_err(|e| fail(e.to_string()))?;
    let wall = start.elapsed().as_secs_f64();
    let output = std::fs::read_to_string(log).unwrap_or_default();
    if let Some(status) = status {
        return Err(fail(format!("{status} after {wall:.1} s:\n{}", tail(&output))));
    }
    let seconds = |t: libc::timeval| t.tv_sec as f64 + t.tv_usec as f64 * 1e-6;
    let cpu = seconds(usage.ru_utime) + seconds(usage.ru_stime);
    Ok((Usage { wall, cpu, peak_bytes: usage.ru_maxrss as u64 * 1024 }, output))
}

/// Waits for `pid` and returns how it failed (None: it exited with 0), and its resource usage.
#[allow(unsafe_code)]
fn reap(pid: libc::pid_t) -> std::io::Result<(Option<String>, libc::rusage)> {
    let mut status = 0;
    // SAFETY: an all-zero rusage is a valid value of this plain C struct.
    let mut usage: libc::rusage = unsafe { std::mem::zeroed() };
    loop {
        // SAFETY: `pid` is our own unreaped child; both pointers are to live locals.
        let r = unsafe { libc::wait4(pid, &mut status, 0, &mut usage) };
        if r == pid {
            let failure = match (libc::WIFEXITED(status), libc::WIFSIGNALED(status)) {
                (true, _) if libc::WEXITSTATUS(status) == 0 => None,
                (true, _) => Some(format!("exit code {}", libc::WEXITSTATUS(status))),
                (_, true) => Some(format!("killed by signal {}", libc::WTERMSIG(status))),
                _ => Some(format!("wait status {status}")),
            };
            return Ok((failure, usage));
        }
        let error = std::io::Error::last_os_error();
        if error.kind() != std::io::ErrorKind::Interrupted {
            return Err(error);
        }
    }
}

fn tail(text: &str) -> String {
    let lines: Vec<&str> = text.lines().collect();
    lines[lines.len().saturating_sub(20)..].join("\n")
}

/// The machine's 1-minute load average (Linux), to print beside the figures.
pub fn load_average() -> Option<f64> {
    std::fs::read_to_string("/proc/loadavg").ok()?.split_whitespace().next()?.parse().ok()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_sample_count_is_read_from_the_run_report() {
        let report = "scene s.toml → out\n\
                      sampling   ran            0.11 s  101371 samples (7 key points)\n\
                      costgraph  ran            0.32 s  101371 nodes, 5068550 edges\n";
        assert_eq!(sample_count(report), Some(101371));
        assert_eq!(sample_count("sampling   up to date     0.00 s\n"), None);
    }
}
