//! The scratch folders of the developer tasks (benches, `bless`, the peer and regional runs):
//! a folder in the temporary folder that is removed when dropped, whether the task succeeds or
//! returns an error half-way, so that no failed run (up to gigabytes) stays behind.

use std::path::{Path, PathBuf};

/// `karstgen-NAME-PID` in the temporary folder, removed with everything in it when dropped.
/// Not created: the task's writers create it.
#[derive(Debug)]
pub struct TempFolder(PathBuf);

impl TempFolder {
    pub fn new(name: &str) -> TempFolder {
        TempFolder(std::env::temp_dir().join(format!("karstgen-{name}-{}", std::process::id())))
    }
}

impl std::ops::Deref for TempFolder {
    type Target = Path;

    fn deref(&self) -> &Path {
        &self.0
    }
}

impl AsRef<Path> for TempFolder {
    fn as_ref(&self) -> &Path {
        &self.0
    }
}

impl Drop for TempFolder {
    fn drop(&mut self) {
        let _ = std::fs::remove_dir_all(&self.0);
    }
}
