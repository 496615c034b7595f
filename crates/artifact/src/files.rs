//! Reading the files a user names (scenes, data files, network files, artifacts) without
//! hanging or exhausting memory: only regular files are opened (a FIFO would block forever,
//! `/dev/zero` never ends), and only up to a size cap, checked before anything is read.

use std::fs::{self, File};
use std::io::{self, Read};
use std::path::Path;

/// Largest scene file read, bytes.
pub const MAX_SCENE_BYTES: u64 = 16 << 20;
/// Largest data file (heightfield, TSurf, TIN, grid) or network file read, bytes.
pub const MAX_DATA_BYTES: u64 = 2 << 30;

/// Opens `path` for reading when it is a regular file of at most `cap` bytes; otherwise an
/// error saying what it is. The type is checked before opening: opening a FIFO blocks.
pub fn open_regular(path: &Path, cap: u64) -> io::Result<(File, u64)> {
    let meta = fs::metadata(path)?;
    let kind = meta.file_type();
    if !kind.is_file() {
        return Err(io::Error::new(
            io::ErrorKind::InvalidInput,
            format!("is not a regular file (it is {})", kind_name(&kind)),
        ));
    }
    if meta.len() > cap {
        return Err(io::Error::new(
            io::ErrorKind::InvalidInput,
            format!(
                "is {} bytes, more than the {cap} bytes such a file may have (docs/limits.md)",
                meta.len()
            ),
        ));
    }
    let file = File::open(path)?;
    Ok((file, meta.len()))
}

/// The bytes of `path`, a regular file of at most `cap` bytes (it may not grow past the cap
/// while being read).
pub fn read_regular(path: &Path, cap: u64) -> io::Result<Vec<u8>> {
    let (file, len) = open_regular(path, cap)?;
    let mut bytes = Vec::with_capacity(len as usize);
    file.take(cap + 1).read_to_end(&mut bytes)?;
    if bytes.len() as u64 > cap {
        return Err(io::Error::new(
            io::ErrorKind::InvalidInput,
            format!("grew past {cap} bytes while being read"),
        ));
    }
    Ok(bytes)
}

/// The text of `path`, a regular UTF-8 file of at most `cap` bytes.
pub fn read_regular_text(path: &Path, cap: u64) -> io::Result<String> {
    String::from_utf8(read_regular(path, cap)?)
        .map_err(|e| io::Error::new(io::ErrorKind::InvalidData, format!("is not UTF-8 text: {e}")))
}

fn kind_name(kind: &fs::FileType) -> &'static str {
    #[cfg(unix)]
    {
        use std::os::unix::fs::FileTypeExt;
        if kind.is_fifo() {
            return "a FIFO";
        }
        if kind.is_char_device() {
            return "a character device";
        }
        if kind.is_block_device() {
            return "a block device";
        }
        if kind.is_socket() {
            return "a socket";
        }
    }
    if kind.is_dir() { "a folder" } else { "not a file" }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    #[allow(unsafe_code)]
    fn devices_folders_and_oversized_files_are_refused() {
        let dir = karst_testkit::scratch("files");
        let err = read_regular(&dir, 10).unwrap_err();
        assert!(err.to_string().contains("a folder"), "{err}");
        #[cfg(unix)]
        {
            let err = read_regular(Path::new("/dev/zero"), 10).unwrap_err();
            assert!(err.to_string().contains("character device"), "{err}");
        }
        #[cfg(unix)]
        {
            let fifo = dir.join("fifo");
            let name = std::ffi::CString::new(fifo.to_string_lossy().as_bytes()).unwrap();
            // SAFETY: mkfifo with a valid NUL-terminated path.
            assert_eq!(unsafe { libc::mkfifo(name.as_ptr(), 0o600) }, 0);
            let err = read_regular(&fifo, 10).unwrap_err();
            assert!(err.to_string().contains("a FIFO"), "{err}");
        }
        let file = dir.join("big.txt");
        fs::write(&file, b"0123456789ab").unwrap();
        assert!(read_regular(&file, 10).unwrap_err().to_string().contains("12 bytes"));
        assert_eq!(read_regular(&file, 12).unwrap(), b"0123456789ab");
    }
}
