//! What karstgen's tests share: where the workspace and its fixtures are, fresh scratch
//! folders, a small scene to start from ([`SceneText`]), running one stage in process, and the
//! command-line contract of the stage binaries ([`cli`]).
//!
//! A dev-dependency of the stage crates; it depends on none of them, so any crate's tests can
//! use it.

use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicUsize, Ordering};

use karst_scene::Scene;
use karst_stage::{Job, Ran, Stage, StageError};

pub mod cli;
pub mod gdal;
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
/// It is removed again when the returned [`Scratch`] is dropped, unless the test is failing
/// (then it stays, to be looked at).
pub fn scratch(name: &str) -> Scratch {
    static CALLS: AtomicUsize = AtomicUsize::new(0);
    let call = CALLS.fetch_add(1, Ordering::Relaxed);
    let dir = std::env::temp_dir().join(format!("karstgen-test-{}-{call}-{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).expect("the temporary folder is writable");
    Scratch(dir)
}

/// A test's scratch folder ([`scratch`]): a path, removed with everything in it when dropped
/// while the thread is not panicking. The suite used to leave every run's folders behind, a
/// run's worth of scratch space each time.
#[derive(Debug)]
pub struct Scratch(PathBuf);

impl Scratch {
    /// The folder as a plain path that is never removed: for a run shared by every test of a
    /// test binary (kept in a static, which is never dropped).
    pub fn keep(mut self) -> PathBuf {
        let path = std::mem::take(&mut self.0);
        std::mem::forget(self);
        path
    }
}

impl std::ops::Deref for Scratch {
    type Target = Path;

    fn deref(&self) -> &Path {
        &self.0
    }
}

impl AsRef<Path> for Scratch {
    fn as_ref(&self) -> &Path {
        &self.0
    }
}

impl Drop for Scratch {
    fn drop(&mut self) {
        if !std::thread::panicking() {
            let _ = std::fs::remove_dir_all(&self.0);
        }
    }
}

/// Runs stage `S` on the scene file `scene` into `out`, as `karst-<stage> run` does.
pub fn run<S: Stage>(scene: &Path, out: &Path) -> Result<Ran, StageError> {
    let loaded = Scene::load(scene)?;
    karst_stage::runner::run::<S>(&Job::new(scene, &loaded, out))
}
