//! Helpers shared by the cross-stage tests: running the pipeline in process, and the docs'
//! references to the repository ([`docs`]).

pub mod docs;

use std::path::{Path, PathBuf};

use karst_artifact::StageId;
use karst_pipeline::make::{self, Selection, StageReport};
use karst_pipeline::scene::SceneFile;
use karst_stage::StageError;

pub use karst_testkit::{root, scratch};

/// Runs the pipeline on `scene` into `out` in this process.
pub fn run(scene: &Path, out: &Path, selection: &Selection) -> Result<Vec<StageReport>, StageError> {
    make::run(&SceneFile::load(scene)?, out, selection, &mut |_| {})
}

/// Runs the pipeline with a rayon pool of `threads` threads.
pub fn run_with_threads(scene: &Path, out: &Path, threads: usize) -> Result<Vec<StageReport>, StageError> {
    let pool = rayon::ThreadPoolBuilder::new().num_threads(threads).build().expect("a thread pool");
    pool.install(|| run(scene, out, &Selection { force: true, ..Selection::default() }))
}

/// The artifact file of every stage in `dir`.
pub fn artifacts(dir: &Path) -> Vec<(StageId, PathBuf)> {
    StageId::ALL.into_iter().map(|s| (s, dir.join(s.file_name()))).collect()
}
