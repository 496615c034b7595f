//! Spill files: a surface's vertices or triangles written to a temporary file as the
//! polygonizer hands them over, then read back in order, as many times as needed, in pieces.
//! The file lies beside the artifact, named `.mesh.SURFACE.WHAT.tmp-PID` so that a killed
//! run's leftover is recognised and removed by the next run
//! (`karst_artifact::atomic::remove_stale_temporaries`); it is removed when the [`Spill`] is
//! dropped, on success and on error alike.

use std::fs::{self, File};
use std::io::{self, BufReader, BufWriter, Read, Write};
use std::marker::PhantomData;
use std::path::{Path, PathBuf};

use karst_artifact::bulk::Element;

/// Bytes read or written at a time.
const BUFFER: usize = 1 << 20;

/// A temporary file of triples of `T` (vertex coordinates, triangle corners), little-endian.
pub(crate) struct Spill<T> {
    path: PathBuf,
    writer: Option<BufWriter<File>>,
    bytes: Vec<u8>,
    len: u64,
    element: PhantomData<T>,
}

impl<T: Element> Spill<T> {
    /// A new, empty spill file `.mesh.NAME.tmp-PID` in `dir`.
    pub(crate) fn create(dir: &Path, name: &str) -> io::Result<Self> {
        let path = dir.join(format!(".mesh.{name}.tmp-{}", std::process::id()));
        let file = File::create(&path).map_err(|e| at(&path, e))?;
        Ok(Spill {
            path,
            writer: Some(BufWriter::with_capacity(BUFFER, file)),
            bytes: Vec::new(),
            len: 0,
            element: PhantomData,
        })
    }

    /// Appends `items`.
    pub(crate) fn push(&mut self, items: &[[T; 3]]) -> io::Result<()> {
        let writer =
            self.writer.as_mut().ok_or_else(|| io::Error::other("a spill written after it was read"))?;
        self.bytes.clear();
        for &value in items.iter().flatten() {
            value.write_le(&mut self.bytes);
        }
        writer.write_all(&self.bytes).map_err(|e| at(&self.path, e))?;
        self.len += items.len() as u64;
        Ok(())
    }

    /// Triples written.
    pub(crate) fn len(&self) -> u64 {
        self.len
    }

    /// Ends the writing; the file can then be read.
    pub(crate) fn finish(&mut self) -> io::Result<()> {
        if let Some(writer) = self.writer.take() {
            writer.into_inner().map_err(|e| at(&self.path, e.into_error()))?;
        }
        Ok(())
    }

    /// A reader from the first triple.
    pub(crate) fn reader(&self) -> io::Result<SpillReader<T>> {
        if self.writer.is_some() {
            return Err(io::Error::other(format!("{}: read before it was finished", self.path.display())));
        }
        let file = File::open(&self.path).map_err(|e| at(&self.path, e))?;
        Ok(SpillReader {
            path: self.path.clone(),
            inner: BufReader::with_capacity(BUFFER, file),
            bytes: Vec::new(),
            element: PhantomData,
        })
    }
}

impl<T> Drop for Spill<T> {
    fn drop(&mut self) {
        self.writer = None;
        let _ = fs::remove_file(&self.path);
    }
}

/// Reads a spill file's triples in order.
pub(crate) struct SpillReader<T> {
    path: PathBuf,
    inner: BufReader<File>,
    bytes: Vec<u8>,
    element: PhantomData<T>,
}

impl<T: Element> SpillReader<T> {
    /// Replaces `out` with the next `n` triples (fewer at the end of the file is an error).
    pub(crate) fn read(&mut self, n: usize, out: &mut Vec<[T; 3]>) -> io::Result<()> {
        out.clear();
        self.bytes.resize(n * 3 * T::WIDTH, 0);
        self.inner.read_exact(&mut self.bytes).map_err(|e| at(&self.path, e))?;
        out.extend(
            self.bytes
                .chunks_exact(3 * T::WIDTH)
                .map(|triple| std::array::from_fn(|i| T::from_le(&triple[i * T::WIDTH..(i + 1) * T::WIDTH]))),
        );
        Ok(())
    }

    /// Calls `each` on every remaining triple, read a buffer at a time.
    pub(crate) fn for_each(
        &mut self,
        total: u64,
        mut each: impl FnMut(&[T; 3]) -> io::Result<()>,
    ) -> io::Result<()> {
        let step = (BUFFER / (3 * T::WIDTH)) as u64;
        let mut chunk = Vec::new();
        let mut done = 0;
        while done < total {
            let n = step.min(total - done);
            self.read(n as usize, &mut chunk)?;
            chunk.iter().try_for_each(&mut each)?;
            done += n;
        }
        Ok(())
    }
}

/// `e` naming the spill file.
fn at(path: &Path, e: io::Error) -> io::Error {
    io::Error::new(e.kind(), format!("{}: {e}", path.display()))
}
