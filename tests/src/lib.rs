//! Helpers shared by the cross-stage tests: where the fixtures are, scratch folders, running
//! the pipeline in process.

use std::path::{Path, PathBuf};

use karst_artifact::{Stage, StageError};
use xtask::executor::InProcess;
use xtask::pipeline::{self, Selection, StageReport};

/// The workspace root.
pub fn root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).parent().expect("tests/ is in the workspace").to_path_buf()
}

/// A fresh, empty scratch folder for one test.
pub fn scratch(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("karstgen-e2e-{}-{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).expect("temp dir is writable");
    dir
}

/// Runs the pipeline on `scene` into `out` in this process.
pub fn run(scene: &Path, out: &Path, selection: &Selection) -> Result<Vec<StageReport>, StageError> {
    pipeline::run(scene, out, selection, &InProcess, false)
}

/// Runs the pipeline with a rayon pool of `threads` threads.
pub fn run_with_threads(scene: &Path, out: &Path, threads: usize) -> Result<Vec<StageReport>, StageError> {
    let pool = rayon::ThreadPoolBuilder::new().num_threads(threads).build().expect("a thread pool");
    pool.install(|| run(scene, out, &Selection { force: true, ..Selection::default() }))
}

/// The artifact file of every stage in `dir`.
pub fn artifacts(dir: &Path) -> Vec<(Stage, PathBuf)> {
    Stage::ALL.into_iter().map(|s| (s, dir.join(s.file_name()))).collect()
}
