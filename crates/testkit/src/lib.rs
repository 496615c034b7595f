//! What karstgen's tests share: where the workspace and its fixtures are, fresh scratch
//! folders, a small scene to start from ([`SceneText`]), and running one stage in process.
//!
//! A dev-dependency of the stage crates; it depends on none of them, so any crate's tests can
//! use it.

use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicUsize, Ordering};

use karst_geology::Scene;
use karst_stage::{Job, Ran, Stage, StageError};

mod scene_text;

pub use scene_text::SceneText;

/// The workspace root.
pub fn root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .ancestors()
        .nth(2)
        .expect("crates/testkit is two levels down")
        .to_path_buf()
}

/// A file or folder of the workspace, from its path relative to the root.
pub fn fixture(relative: &str) -> PathBuf {
    root().join(relative)
}

/// A fresh, empty folder for one test: unique per process and call, removed first if present.
pub fn scratch(name: &str) -> PathBuf {
    static CALLS: AtomicUsize = AtomicUsize::new(0);
    let call = CALLS.fetch_add(1, Ordering::Relaxed);
    let dir = std::env::temp_dir().join(format!("karstgen-test-{}-{call}-{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).expect("the temporary folder is writable");
    dir
}

/// Runs stage `S` on the scene file `scene` into `out`, as `karst-<stage> run` does.
pub fn run<S: Stage>(scene: &Path, out: &Path) -> Result<Ran, StageError> {
    let loaded = Scene::load(scene)?;
    karst_stage::runner::run::<S>(&Job { scene_path: scene, scene: &loaded, out })
}
