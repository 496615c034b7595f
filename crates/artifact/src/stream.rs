//! A bulk payload decoded from the file as it is read, so that its bytes and the decoded arrays
//! are never in memory together: reading costgraph.bin whole and then decoding it held the
//! payload twice, twice the memory of the regional scene's payload of gigabytes.
//!
//! A payload type that opts in ([`crate::Payload::read_streamed`]) reads its fields in
//! postcard's order through a [`PayloadReader`]: numbers and small fields one by one, bulk
//! arrays ([`crate::bulk`]: a varint byte length, then little-endian values) straight into their
//! vectors through a buffer of a few MiB. The reader hashes and counts every byte it passes on,
//! so the envelope checks the same length and BLAKE3 digest as for a payload read whole; and it
//! never allocates for a length larger than what is left of the header's payload length, so a
//! corrupted length fails (then reads as a checksum error) instead of exhausting memory.

use std::io::Read;

use crate::bulk::Element;
use crate::error::DecodeError;
use crate::hash;

/// Bytes read from the file at a time into a bulk array.
const CHUNK: usize = 4 << 20;

/// The payload's bytes as they are read: hashed, counted, bounded by the header's length.
pub struct PayloadReader<'r> {
    source: &'r mut dyn Read,
    hasher: blake3::Hasher,
    read: u64,
    len: u64,
    buffer: Vec<u8>,
}

impl<'r> PayloadReader<'r> {
    /// Reads a payload of `len` bytes (the header's) from `source`.
    pub fn new(source: &'r mut dyn Read, len: u64) -> Self {
        PayloadReader { source, hasher: blake3::Hasher::new(), read: 0, len, buffer: Vec::new() }
    }

    /// Bytes of the payload not read yet.
    fn left(&self) -> u64 {
        self.len.saturating_sub(self.read)
    }

    /// Reads the next `n` bytes (at most [`CHUNK`]) into the buffer and hashes them.
    fn fill(&mut self, n: usize) -> Result<&[u8], DecodeError> {
        let mut buffer = std::mem::take(&mut self.buffer);
        buffer.resize(n, 0);
        let read = self.read_into(&mut buffer);
        self.buffer = buffer;
        read.map(|()| self.buffer.as_slice())
    }

    /// Fills `out` with the next bytes of the payload and hashes them.
    fn read_into(&mut self, out: &mut [u8]) -> Result<(), DecodeError> {
        let n = out.len();
        if n as u64 > self.left() {
            return Err(DecodeError::Short { wanted: n as u64, left: self.left() });
        }
        let mut got = 0;
        while got < n {
            match self.source.read(&mut out[got..]) {
                Ok(0) => break,
                Ok(k) => got += k,
                Err(e) if e.kind() == std::io::ErrorKind::Interrupted => {}
                Err(e) => return Err(DecodeError::Io { at: self.read + got as u64, reason: e.to_string() }),
            }
        }
        // What was read is hashed and counted even when it falls short, so that the envelope
        // reports the payload's true length.
        hash::update(&mut self.hasher, &out[..got]);
        self.read += got as u64;
        if got < n {
            return Err(DecodeError::Truncated(self.read));
        }
        Ok(())
    }

    /// One byte.
    pub fn byte(&mut self) -> Result<u8, DecodeError> {
        Ok(self.fill(1)?[0])
    }

    /// A postcard varint (LEB128, at most 10 bytes for 64 bits).
    pub fn varint(&mut self) -> Result<u64, DecodeError> {
        let mut value = 0u64;
        for i in 0..10 {
            let b = self.byte()?;
            value |= u64::from(b & 0x7f) << (7 * i);
            if b & 0x80 == 0 {
                return Ok(value);
            }
        }
        Err(DecodeError::LongVarint)
    }

    /// A length that must fit in what is left of the payload.
    pub fn length(&mut self) -> Result<usize, DecodeError> {
        let n = self.varint()?;
        if n > self.left() {
            return Err(DecodeError::Length { length: n, left: self.left() });
        }
        Ok(n as usize)
    }

    /// The next `n` bytes.
    pub fn bytes(&mut self, n: usize) -> Result<Vec<u8>, DecodeError> {
        if n as u64 > self.left() {
            return Err(DecodeError::Short { wanted: n as u64, left: self.left() });
        }
        let mut out = Vec::with_capacity(n);
        while out.len() < n {
            let step = (n - out.len()).min(CHUNK);
            out.extend_from_slice(self.fill(step)?);
        }
        Ok(out)
    }

    /// A bulk array ([`crate::bulk::serialize`]): its byte length, then its values.
    pub fn bulk<T: Element>(&mut self) -> Result<Vec<T>, DecodeError> {
        let n = self.length()?;
        if !n.is_multiple_of(T::WIDTH) {
            return Err(DecodeError::BulkWidth { width: T::WIDTH, bytes: n });
        }
        self.bulk_values(n / T::WIDTH)
    }

    /// `count` values of a bulk array, read straight into their vector (little-endian machines:
    /// the file's bytes are the values' memory, so no copy through the buffer), a chunk at a
    /// time so that each is hashed while it is in cache.
    #[cfg(target_endian = "little")]
    fn bulk_values<T: Element>(&mut self, count: usize) -> Result<Vec<T>, DecodeError> {
        let mut values = vec![T::ZERO; count];
        for piece in crate::bulk::le_bytes_mut(&mut values).chunks_mut(CHUNK) {
            self.read_into(piece)?;
        }
        Ok(values)
    }

    #[cfg(not(target_endian = "little"))]
    fn bulk_values<T: Element>(&mut self, count: usize) -> Result<Vec<T>, DecodeError> {
        let mut values = Vec::with_capacity(count);
        let mut left = count * T::WIDTH;
        while left > 0 {
            let step = left.min(CHUNK - CHUNK % T::WIDTH);
            values.extend(self.fill(step)?.chunks_exact(T::WIDTH).map(T::from_le));
            left -= step;
        }
        Ok(values)
    }

    /// The rest of the payload, a small tail, decoded with postcard to its last byte.
    pub fn tail<T: serde::de::DeserializeOwned>(&mut self) -> Result<T, DecodeError> {
        let rest = self.bytes(self.left() as usize)?;
        crate::whole::postcard_whole(&rest)
    }

    /// Bytes of the payload decoded so far.
    pub(crate) fn position(&self) -> u64 {
        self.read
    }

    /// Reads whatever the source still holds (past the payload too: a longer file is a length
    /// error) and returns the number of bytes read in all and their digest.
    pub fn finish(mut self) -> std::io::Result<(u64, String)> {
        let mut buffer = std::mem::take(&mut self.buffer);
        buffer.resize(CHUNK, 0);
        loop {
            let n = match self.source.read(&mut buffer) {
                Ok(0) => break,
                Ok(n) => n,
                Err(e) if e.kind() == std::io::ErrorKind::Interrupted => continue,
                Err(e) => return Err(e),
            };
            hash::update(&mut self.hasher, &buffer[..n]);
            self.read += n as u64;
        }
        Ok((self.read, self.hasher.finalize().to_hex().to_string()))
    }
}
