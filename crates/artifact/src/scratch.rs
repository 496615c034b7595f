//! The unit tests' scratch folders. `karst_testkit::scratch` cannot be used here (the test kit
//! depends on this crate), so this is its small private twin: a fresh folder per test, removed
//! when the test passes, kept when it fails (to be looked at).

use std::path::{Path, PathBuf};

/// A fresh, empty folder `karst-artifact-PID-name` in the temporary folder.
pub fn scratch(name: &str) -> Scratch {
    let dir = std::env::temp_dir().join(format!("karst-artifact-{}-{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).expect("the temporary folder is writable");
    Scratch(dir)
}

/// A scratch folder, removed with everything in it when dropped while the thread is not
/// panicking.
pub struct Scratch(PathBuf);

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
