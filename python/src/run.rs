//! The pipeline from Python, as `karstgen run` runs it (stages skipped when up to date), in a
//! worker thread: the calling thread waits with the GIL released, so other Python threads run,
//! and checks for signals every 50 ms, so Ctrl-C raises `KeyboardInterrupt` at once. The
//! worker then stops before the next stage (a stage's artifact is written atomically: an
//! interrupted stage leaves the previous artifact or none).

use std::path::PathBuf;
use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::mpsc::{self, RecvTimeoutError};
use std::time::Duration;

use pyo3::prelude::*;

use karst_artifact::StageId;
use karst_pipeline::make::{self, Outcome, Selection, StageReport};
use karst_pipeline::scene::SceneFile;
use karst_scene::Scene;
use karst_stage::StageError;

use crate::errors::{KarstgenError, argument, to_py};

/// One line of a run's report: stage, status (`ran`, `up to date`), seconds, headline.
type Line = (String, String, f64, String);

/// Runs the scene `(path, text)` into `out` up to the stage `until` (every stage when None),
/// with `seed` instead of the scene's, on `threads` threads (None: all cores).
#[pyfunction]
#[pyo3(signature = (path, text, out, until=None, seed=None, force=false, threads=None))]
#[allow(clippy::too_many_arguments)]
pub fn run(
    py: Python<'_>,
    path: PathBuf,
    text: String,
    out: PathBuf,
    until: Option<String>,
    seed: Option<u64>,
    force: bool,
    threads: Option<usize>,
) -> PyResult<Vec<Line>> {
    let until = stage_named(until.as_deref())?;
    let cancel = Arc::new(AtomicBool::new(false));
    let (sender, receiver) = mpsc::channel();
    let stop = cancel.clone();
    std::thread::Builder::new()
        .name("karstgen-run".into())
        .spawn(move || {
            let result = std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| {
                with_threads(threads, || pipeline(&path, &text, &out, until, seed, force, &stop))
            }))
            .unwrap_or_else(|_| Err(StageError::failure("karstgen panicked (see the message above)")));
            let _ = sender.send(result);
        })
        .map_err(|e| KarstgenError::new_err(format!("cannot start the run's thread: {e}")))?;
    let mut receiver = receiver;
    loop {
        // The receiver is not Sync: it moves into the GIL-free closure and back.
        let (received, back) =
            py.detach(move || (receiver.recv_timeout(Duration::from_millis(50)), receiver));
        receiver = back;
        match received {
            Ok(result) => return result.map(|reports| reports.iter().map(line).collect()).map_err(to_py),
            Err(RecvTimeoutError::Timeout) => {
                if let Err(interrupt) = py.check_signals() {
                    cancel.store(true, Ordering::Relaxed);
                    return Err(interrupt);
                }
            }
            Err(RecvTimeoutError::Disconnected) => {
                return Err(KarstgenError::new_err("the run's thread ended without a result"));
            }
        }
    }
}

/// The stage called `name`, if any.
pub fn stage_named(name: Option<&str>) -> PyResult<Option<StageId>> {
    name.map(|n| {
        StageId::from_name(n).ok_or_else(|| {
            let names: Vec<&str> = StageId::ALL.iter().map(|s| s.name()).collect();
            argument(format!("unknown stage \"{n}\"; stages: {}", names.join(", ")))
        })
    })
    .transpose()
}

/// Runs `work` on a pool of `threads` threads (the global pool when None).
pub fn with_threads<T: Send>(
    threads: Option<usize>,
    work: impl FnOnce() -> Result<T, StageError> + Send,
) -> Result<T, StageError> {
    match threads {
        None => work(),
        Some(n) => rayon::ThreadPoolBuilder::new()
            .num_threads(n.max(1))
            .build()
            .map_err(|e| StageError::failure(format!("cannot start {n} threads: {e}")))?
            .install(work),
    }
}

/// The stages one by one, stopping between two when `cancel` is set.
fn pipeline(
    path: &std::path::Path,
    text: &str,
    out: &std::path::Path,
    until: Option<StageId>,
    seed: Option<u64>,
    force: bool,
    cancel: &AtomicBool,
) -> Result<Vec<StageReport>, StageError> {
    let mut scene = SceneFile { path: path.to_path_buf(), scene: Scene::parse(text, path)? };
    if let Some(seed) = seed {
        scene = scene.with_seed(seed);
    }
    let mut reports = Vec::new();
    for stage in StageId::ALL.into_iter().filter(|s| until.is_none_or(|u| *s <= u)) {
        if cancel.load(Ordering::Relaxed) {
            return Err(StageError::failure("interrupted"));
        }
        let selection = Selection { from: force.then_some(stage), to: Some(stage), ..Selection::default() };
        make::run(&scene, out, &selection, &mut |report| {
            if report.stage == stage {
                reports.push(report.clone());
            }
        })?;
    }
    Ok(reports)
}

fn line(report: &StageReport) -> Line {
    let (status, headline) = match &report.outcome {
        Outcome::Ran { headline, .. } => ("ran", headline.clone()),
        Outcome::UpToDate => ("up to date", String::new()),
        Outcome::Skipped => ("skipped", String::new()),
    };
    (report.stage.name().to_string(), status.to_string(), report.seconds, headline)
}
