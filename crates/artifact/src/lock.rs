//! One writer per output folder: a run (or a stage binary's `run`) holds an advisory lock on
//! `DIR/.karstgen.lock` while it writes into DIR, so that two runs into one folder never mix
//! their artifacts or delete each other's temporary files. The operating system releases the
//! lock when the process ends, however it ends, so a killed run never leaves the folder locked.

use std::fs::{self, File, OpenOptions, TryLockError};
use std::path::{Path, PathBuf};

use crate::error::Error;

/// The lock file's name inside the output folder.
pub const LOCK_FILE: &str = ".karstgen.lock";

/// The lock on an output folder, released when dropped.
#[derive(Debug)]
pub struct OutputLock {
    _file: File,
    dir: PathBuf,
}

impl OutputLock {
    /// The locked folder.
    pub fn dir(&self) -> &Path {
        &self.dir
    }
}

/// Locks `dir` (created when missing) for writing, or fails at once with
/// [`Error::Busy`] when another process holds it.
pub fn lock_output(dir: &Path) -> Result<OutputLock, Error> {
    let io = |source| Error::Write { path: dir.join(LOCK_FILE), source };
    fs::create_dir_all(dir).map_err(io)?;
    let file = OpenOptions::new()
        .read(true)
        .write(true)
        .create(true)
        .truncate(false)
        .open(dir.join(LOCK_FILE))
        .map_err(io)?;
    match file.try_lock() {
        Ok(()) => Ok(OutputLock { _file: file, dir: dir.to_path_buf() }),
        Err(TryLockError::WouldBlock) => Err(Error::Busy { dir: dir.to_path_buf() }),
        Err(TryLockError::Error(source)) => Err(io(source)),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_second_writer_is_refused_until_the_first_is_done() {
        let scratch = karst_testkit::scratch("lock");
        let dir = scratch.join("out");
        let first = lock_output(&dir).unwrap();
        let err = lock_output(&dir).unwrap_err();
        assert!(err.to_string().contains("another run is writing to"), "{err}");
        assert!(!err.is_bad_input());
        drop(first);
        let again = lock_output(&dir).unwrap();
        assert_eq!(again.dir(), dir);
    }
}
