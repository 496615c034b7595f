//! `cargo xtask realism-defaults [--write]`: how cave-like the network's defaults are on scenes
//! the presets never saw (issue 38). A fixed distribution of scenes ([`population`]: extents
//! 0.3–10 km, three kinds of terrain, 2–30 sinks, 1–3 springs, no `[skeleton]` section) is drawn
//! twice, from a tuning set of scene seeds (on which the defaults were chosen) and from a
//! held-out set (on which they are reported); every scene runs the network half (sampling, cost
//! graph, skeleton, karstnet's statistics) in process for three seeds, one realization per core.
//!
//! The table gives, per set, the share of realizations inside all ten real-cave ranges, inside
//! at least eight, and inside each metric's range; a realization that fails counts as outside
//! every range. With `--write` the table replaces docs/metrics.md's section between
//! `<!-- realism-table -->` and `<!-- /realism-table -->`.

pub mod population;
pub mod terrain;

use std::fmt::Write as _;
use std::path::{Path, PathBuf};

use std::sync::atomic::{AtomicUsize, Ordering};

use karst_artifact::{StageId, read_artifact};
use karst_metrics::ranges::{CHARACTERIZE_KEYS, real_cave_ranges};
use karst_pipeline::registry;
use karst_pipeline::scene::SceneFile;
use karst_scene::budget::Budget;
use karst_skeleton::Skeleton;
use karst_stage::{Handoff, Job, StageError};

pub const BEGIN: &str = "<!-- realism-table -->";
pub const END: &str = "<!-- /realism-table -->";

/// Scenes per set.
pub const SCENES: u64 = 32;
/// Realizations (seeds) per scene.
pub const SEEDS: u64 = 3;

/// How much of a set runs: its first `scenes` scenes, `seeds` realizations each.
#[derive(Debug, Clone, Copy)]
pub struct Subset {
    pub scenes: u64,
    pub seeds: u64,
}

impl Subset {
    /// Every scene, every seed: the figures reported.
    pub const FULL: Subset = Subset { scenes: SCENES, seeds: SEEDS };
    /// Twelve scenes, one seed each: a quick look while iterating on a rule.
    pub const QUICK: Subset = Subset { scenes: 12, seeds: 1 };
}

/// The two sets of scene seeds: the defaults are chosen on the first, reported on the second.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Set {
    Tuning,
    HeldOut,
}

impl Set {
    pub fn name(self) -> &'static str {
        match self {
            Set::Tuning => "tuning",
            Set::HeldOut => "held-out",
        }
    }

    /// Its first `n` scene seeds.
    pub fn scene_seeds(self, n: u64) -> std::ops::Range<u64> {
        let first = match self {
            Set::Tuning => 1,
            Set::HeldOut => 1001,
        };
        first..first + n
    }
}

/// The first `n` realization seeds of a scene.
fn seeds_of(scene_seed: u64, n: u64) -> impl Iterator<Item = u64> {
    (0..n).map(move |k| scene_seed * 100 + k)
}

/// Memory a realization may plan to use: scenes whose defaults ask for more fail (and count
/// as outside every range) rather than swap.
const BUDGET_BYTES: u64 = 512 << 20;

/// One realization's result: which metrics are inside, or why it failed.
#[derive(Debug, Clone)]
pub struct Outcome {
    pub scene: String,
    pub seed: u64,
    pub result: Result<Vec<(String, f64, bool)>, String>,
}

impl Outcome {
    pub fn inside_count(&self) -> usize {
        self.result.as_ref().map_or(0, |m| m.iter().filter(|(_, _, inside)| *inside).count())
    }

    fn inside(&self, key: &str) -> bool {
        self.result.as_ref().is_ok_and(|m| m.iter().any(|(k, _, inside)| k == key && *inside))
    }
}

/// Generates the scenes of `subset` of `set` under `out` and runs every realization.
pub fn run_set(set: Set, subset: Subset, out: &Path) -> Result<Vec<Outcome>, StageError> {
    let dir = out.join(set.name());
    std::fs::create_dir_all(&dir).map_err(|e| StageError::failure(format!("{}: {e}", dir.display())))?;
    let scenes = set
        .scene_seeds(subset.scenes)
        .map(|s| population::generate(s, &dir))
        .collect::<std::io::Result<Vec<_>>>()
        .map_err(|e| StageError::failure(format!("{}: {e}", dir.display())))?;
    let jobs: Vec<(&population::Generated, u64)> =
        scenes.iter().flat_map(|g| seeds_of(g.scene_seed, subset.seeds).map(move |s| (g, s))).collect();
    // One worker per core takes the next realization; the stages inside use rayon's pool
    // themselves (the skeleton's helper threads wait on it, so the workers must not be its
    // threads).
    let next = AtomicUsize::new(0);
    let workers = std::thread::available_parallelism().map_or(1, |n| n.get());
    let mut outcomes: Vec<(usize, Outcome)> = std::thread::scope(|scope| {
        let handles: Vec<_> = (0..workers)
            .map(|_| {
                scope.spawn(|| {
                    let mut done = Vec::new();
                    loop {
                        let i = next.fetch_add(1, Ordering::Relaxed);
                        let Some(&(g, seed)) = jobs.get(i) else { break };
                        let result = realize(&g.path, seed, &dir).map_err(|e| e.to_string());
                        let outcome = Outcome { scene: g.label.clone(), seed, result };
                        eprintln!("{} {}", set.name(), describe(&outcome));
                        done.push((i, outcome));
                    }
                    done
                })
            })
            .collect();
        handles.into_iter().flat_map(|h| h.join().unwrap_or_default()).collect()
    });
    outcomes.sort_by_key(|(i, _)| *i);
    Ok(outcomes.into_iter().map(|(_, o)| o).collect())
}

/// One line for a realization: the inside count and the metrics outside.
pub fn describe(o: &Outcome) -> String {
    match &o.result {
        Ok(metrics) => {
            let values: Vec<String> = metrics
                .iter()
                .map(|(k, v, inside)| format!("{}{k} {v:.3}", if *inside { "" } else { "OUT " }))
                .collect();
            format!("{} seed {}: {}/10: {}", o.scene, o.seed, o.inside_count(), values.join(", "))
        }
        Err(e) => format!("{} seed {}: failed: {e}", o.scene, o.seed),
    }
}

/// The network half of `scene` for `seed`, in `dir/<scene>-<seed>`; karstnet's ten metrics,
/// each with whether it lies in the real-cave range.
fn realize(scene: &Path, seed: u64, dir: &Path) -> Result<Vec<(String, f64, bool)>, StageError> {
    let loaded = SceneFile::load(scene)?.with_seed(seed);
    let mut scene_data = loaded.scene.clone();
    scene_data.set_budget(Budget { bytes: BUDGET_BYTES });
    let stem = scene.file_stem().map(|s| s.to_string_lossy().into_owned()).unwrap_or_default();
    let out = dir.join(format!("{stem}-{seed}"));
    std::fs::create_dir_all(&out).map_err(|e| StageError::failure(format!("{}: {e}", out.display())))?;
    let handoff = Handoff::new();
    let job = Job { handoff: Some(&handoff), ..Job::new(&loaded.path, &scene_data, &out) };
    for stage in [StageId::Sampling, StageId::Costgraph, StageId::Skeleton] {
        handoff.begin(stage);
        registry::stage(stage).run(&job)?;
    }
    let (_, skeleton) = read_artifact::<Skeleton>(&job.artifact(StageId::Skeleton))?;
    let report = karst_metrics::report(&skeleton).map_err(|e| StageError::failure(e.to_string()))?;
    let _ = std::fs::remove_dir_all(&out);
    Ok(CHARACTERIZE_KEYS
        .iter()
        .map(|k| (k.to_string(), report.karstnet[*k].value, report.karstnet[*k].inside))
        .collect())
}

/// The Markdown table of both sets: one row per figure, one column per set.
pub fn markdown(sets: &[(Set, Vec<Outcome>)], subset: Subset) -> String {
    let ranges = real_cave_ranges();
    let share = |outcomes: &[Outcome], pass: &dyn Fn(&Outcome) -> bool| {
        let n = outcomes.iter().filter(|o| pass(o)).count();
        format!("{:.0} % ({n}/{})", 100.0 * n as f64 / outcomes.len().max(1) as f64, outcomes.len())
    };
    let mut out = format!(
        "{} scenes per set × {} seeds, defaults only (no `[skeleton]`); `cargo xtask realism-defaults --write`.\n\n| share of realizations |",
        subset.scenes, subset.seeds
    );
    for (set, _) in sets {
        let _ = write!(out, " {} |", set.name());
    }
    out += " real caves |\n|---|";
    out += &"---:|".repeat(sets.len());
    out += "---|\n";
    let mut row = |label: String, pass: &dyn Fn(&Outcome) -> bool, range: String| {
        let _ = write!(out, "| {label} |");
        for (_, outcomes) in sets {
            let _ = write!(out, " {} |", share(outcomes, pass));
        }
        let _ = writeln!(out, " {range} |");
    };
    row("**inside all ten**".into(), &|o| o.inside_count() == 10, String::new());
    row("**inside at least eight**".into(), &|o| o.inside_count() >= 8, String::new());
    for key in CHARACTERIZE_KEYS {
        let r = &ranges[key];
        row(key.to_string(), &|o| o.inside(key), format!("{} – {}", short(r.min), short(r.max)));
    }
    row("failed runs".into(), &|o| o.result.is_err(), String::new());
    out
}

fn short(v: f64) -> String {
    if v.abs() >= 100.0 { format!("{v:.0}") } else { format!("{v:.3}") }
}

/// The scratch folder of the population.
pub fn out_dir() -> PathBuf {
    PathBuf::from("out/realism")
}
