//! Atomic file replacement: write a temporary file in the target's folder, fsync it, rename it
//! over the target, fsync the folder. A process killed at any point leaves either the old file
//! or the new one, never a torn file. Temporary files are named `.NAME.tmp-PID` so that a crash
//! leftover is recognisable; they are removed on the next write of the same file and when a run
//! starts ([`remove_stale_temporaries`]), but only when process PID is gone: a temporary file of
//! a live process is another write in progress, never ours to delete.

use std::fs::{self, File, OpenOptions};
use std::io::{self, Write};
use std::path::{Path, PathBuf};

/// Atomically replaces `path` with the bytes produced by `fill`.
pub fn write_with(path: &Path, fill: impl FnOnce(&mut dyn Write) -> io::Result<()>) -> io::Result<()> {
    let dir = parent_dir(path);
    fs::create_dir_all(&dir)?;
    remove_leftovers(path);
    let tmp = temp_path(path);
    let result = (|| {
        let mut file = OpenOptions::new().write(true).create_new(true).open(&tmp)?;
        {
            let mut writer = io::BufWriter::with_capacity(1 << 20, &mut file);
            fill(&mut writer)?;
            writer.flush()?;
        }
        file.sync_all()?;
        drop(file);
        fs::rename(&tmp, path)?;
        // Make the rename itself durable. Not every platform can open a folder; that is not fatal.
        if let Ok(d) = File::open(&dir) {
            let _ = d.sync_all();
        }
        Ok(())
    })();
    if result.is_err() {
        let _ = fs::remove_file(&tmp);
    }
    result
}

/// Atomically replaces `path` with `bytes`.
pub fn write_bytes(path: &Path, bytes: &[u8]) -> io::Result<()> {
    write_with(path, |w| w.write_all(bytes))
}

fn parent_dir(path: &Path) -> PathBuf {
    match path.parent() {
        Some(p) if !p.as_os_str().is_empty() => p.to_path_buf(),
        _ => PathBuf::from("."),
    }
}

fn file_name(path: &Path) -> String {
    path.file_name().map(|n| n.to_string_lossy().into_owned()).unwrap_or_default()
}

fn temp_path(path: &Path) -> PathBuf {
    parent_dir(path).join(format!(".{}.tmp-{}", file_name(path), std::process::id()))
}

/// Removes temporary files left by earlier, interrupted writes of `path`.
fn remove_leftovers(path: &Path) {
    let prefix = format!(".{}.tmp-", file_name(path));
    let Ok(entries) = fs::read_dir(parent_dir(path)) else { return };
    for entry in entries.flatten() {
        let name = entry.file_name().to_string_lossy().into_owned();
        if name.starts_with(&prefix) && writer_is_gone(&name) {
            let _ = fs::remove_file(entry.path());
        }
    }
}

/// Removes every `.NAME.tmp-PID` file of a process that no longer runs from `dir` and its
/// sub-folders (exports, previews), and every such folder (the viewer's staging folder
/// `.view.tmp-PID`): what a killed run left behind. Returns how many.
pub fn remove_stale_temporaries(dir: &Path) -> usize {
    let Ok(entries) = fs::read_dir(dir) else { return 0 };
    let mut removed = 0;
    for entry in entries.flatten() {
        let name = entry.file_name().to_string_lossy().into_owned();
        let Ok(kind) = entry.file_type() else { continue };
        if kind.is_dir() && is_temporary(&name) && writer_is_gone(&name) {
            removed += usize::from(fs::remove_dir_all(entry.path()).is_ok());
        } else if kind.is_dir() {
            removed += remove_stale_temporaries(&entry.path());
        } else if kind.is_file() && is_temporary(&name) && writer_is_gone(&name) {
            removed += usize::from(fs::remove_file(entry.path()).is_ok());
        }
    }
    removed
}

/// True for a name `.NAME.tmp-PID`.
fn is_temporary(name: &str) -> bool {
    name.starts_with('.') && pid_of(name).is_some()
}

fn pid_of(name: &str) -> Option<u32> {
    let (_, pid) = name.rsplit_once(".tmp-")?;
    pid.parse().ok()
}

/// True when the process that named the temporary file `name` no longer runs.
fn writer_is_gone(name: &str) -> bool {
    pid_of(name).is_some_and(|pid| !process_runs(pid))
}

/// Whether process `pid` exists (signal 0 probes without sending anything); elsewhere than
/// Unix, assume it does, so that nothing in use is deleted.
#[allow(unsafe_code)]
fn process_runs(pid: u32) -> bool {
    #[cfg(unix)]
    {
        let Ok(pid) = libc::pid_t::try_from(pid) else { return false };
        // SAFETY: kill with signal 0 only checks that the process exists.
        let found = unsafe { libc::kill(pid, 0) } == 0;
        found || io::Error::last_os_error().raw_os_error() == Some(libc::EPERM)
    }
    #[cfg(not(unix))]
    {
        let _ = pid;
        true
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use karst_testkit::scratch;

    #[test]
    fn failed_write_keeps_the_old_file() {
        let dir = scratch("atomic-fail");
        let target = dir.join("a.bin");
        write_bytes(&target, b"old").unwrap();
        let err = write_with(&target, |w| {
            w.write_all(b"half")?;
            Err(io::Error::other("killed"))
        });
        assert!(err.is_err());
        assert_eq!(fs::read(&target).unwrap(), b"old");
        assert_eq!(fs::read_dir(&dir).unwrap().count(), 1, "no temporary file left behind");
    }

    /// A process id that is not running: the child of a finished command.
    fn dead_pid() -> u32 {
        let mut child = std::process::Command::new("true").spawn().unwrap();
        let pid = child.id();
        child.wait().unwrap();
        pid
    }

    #[test]
    fn leftovers_of_a_crash_are_cleaned() {
        let dir = scratch("atomic-leftover");
        let target = dir.join("b.bin");
        fs::write(dir.join(format!(".b.bin.tmp-{}", dead_pid())), b"torn").unwrap();
        write_bytes(&target, b"new").unwrap();
        assert_eq!(fs::read(&target).unwrap(), b"new");
        assert_eq!(fs::read_dir(&dir).unwrap().count(), 1);
    }

    #[test]
    fn a_live_writer_keeps_its_temporary_file() {
        // Another process writing the same file: its temporary file must survive our write.
        let dir = scratch("atomic-live");
        let target = dir.join("c.bin");
        let live = dir.join(format!(".c.bin.tmp-{}", std::os::unix::process::parent_id()));
        fs::write(&live, b"in progress").unwrap();
        write_bytes(&target, b"ours").unwrap();
        assert!(live.exists());
        assert_eq!(remove_stale_temporaries(&dir), 0);
        let stale = dir.join("export").join(format!(".cave.obj.tmp-{}", dead_pid()));
        fs::create_dir_all(stale.parent().unwrap()).unwrap();
        fs::write(&stale, b"torn").unwrap();
        assert_eq!(remove_stale_temporaries(&dir), 1);
        assert!(!stale.exists() && live.exists());
        // A staging folder of a killed viewer goes whole; a live one stays.
        let (dead, alive) = (dir.join(format!(".view.tmp-{}", dead_pid())), dir.join(".view.tmp-1"));
        for staging in [&dead, &alive] {
            fs::create_dir_all(staging.join("data")).unwrap();
            fs::write(staging.join("data/run.json"), b"{}").unwrap();
        }
        assert_eq!(remove_stale_temporaries(&dir), 1);
        assert!(!dead.exists() && alive.join("data/run.json").exists());
    }
}
