//! The artifact file format: a [`Header`] and the payload, in one of two layouts.
//!
//! - Bulk payloads (samples, costgraph, sdf, mesh) are encoded with postcard (a maintained serde
//!   codec with a stable, documented wire format; see the README for the measurement that chose
//!   it over bincode 2): the file is the header as one line of JSON, then the payload bytes.
//! - Small payloads (skeleton, hydro, metrics) are pretty JSON, so that a review or CI diff is
//!   readable, and the whole file is one JSON document that any JSON parser reads:
//!
//!   ```text
//!   {"header":{"format":"karstgen-artifact",...},
//!   "payload":
//!   { ...the payload, pretty-printed... }
//!   }
//!   ```
//!
//!   The first line is `{"header":` + the header + `,`, the second `"payload":`; the payload's
//!   bytes run from the third line to the file's last line, which is `}`. `payload_len` and
//!   `payload_blake3` cover exactly those payload bytes, so both layouts are checked alike.

use std::fs;
use std::io::{BufRead, BufReader, Read, Write};
use std::path::Path;

use serde::de::DeserializeOwned;
use serde::{Deserialize, Serialize};

use crate::error::{DecodeError, Error};
use crate::frame::Frame;
use crate::stages::{Encoding, StageId, stage_key};
use crate::stream::PayloadReader;
use crate::whole::{postcard_whole, read_to_the_end};
use crate::{atomic, hash};

/// The value of the header's `format` field.
pub const FORMAT: &str = "karstgen-artifact";

/// Longest header line accepted; anything longer is not one of ours.
const MAX_HEADER_LEN: u64 = 64 * 1024;

/// How a JSON artifact's first line starts, and its second line.
const JSON_OPEN: &[u8] = b"{\"header\":";
const JSON_PAYLOAD: &[u8] = b"\"payload\":\n";
/// How a JSON artifact ends, after the payload's bytes.
const JSON_CLOSE: &[u8] = b"}\n";

/// One upstream artifact an artifact was made from.
#[derive(Debug, Clone, PartialEq, Eq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct InputRef {
    /// The upstream artifact's kind name.
    pub name: String,
    /// BLAKE3 of the upstream payload.
    pub payload_blake3: String,
}

/// The first line of every artifact file.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Header {
    pub format: String,
    pub kind: StageId,
    pub schema: u32,
    pub producer: String,
    pub encoding: Encoding,
    pub key: String,
    pub inputs: Vec<InputRef>,
    pub params: String,
    /// World coordinates of the local frame's origin (absent in files written before it was
    /// recorded: [0, 0, 0], which is what they used).
    #[serde(default)]
    pub origin: [f64; 3],
    /// The scene's coordinate reference system, if it names one.
    #[serde(default)]
    pub crs: Option<String>,
    pub payload_len: u64,
    pub payload_blake3: String,
}

/// Where an artifact comes from: who made it, from which inputs and scene sections, in which
/// frame. The key is derived from it and the payload's schema when the artifact is written.
#[derive(Debug, Clone, PartialEq)]
pub struct Provenance {
    pub producer: String,
    pub inputs: Vec<InputRef>,
    pub params: String,
    pub frame: Frame,
}

impl Header {
    /// The local frame the payload's coordinates are in.
    pub fn frame(&self) -> Frame {
        Frame { origin: self.origin, crs: self.crs.clone() }
    }
}

/// A type that is the payload of one stage's artifact.
pub trait Payload: Serialize + DeserializeOwned {
    /// The stage that writes it.
    const STAGE: StageId;
    /// Bumped on every change of the payload's layout or meaning.
    const SCHEMA: u32;

    /// Checks what decoding cannot: indices in range, counts consistent, numbers finite and in
    /// their physical range. Called once on every payload read, before anything uses it, so
    /// that a file with a right checksum but wrong content is an error naming the field, not a
    /// panic or a silent wrong result downstream.
    fn validate(&self) -> Result<(), Invalid> {
        Ok(())
    }

    /// Decodes a postcard payload from its bytes as they are read ([`PayloadReader`]: hashed,
    /// counted, bounded by the header's length), for bulk payloads too large to hold twice in
    /// memory ([`crate::stream`]). None, the default, without reading anything: the payload is
    /// read whole, checked, then decoded.
    fn read_streamed(_bytes: &mut PayloadReader) -> Option<Result<Self, DecodeError>> {
        None
    }
}

/// What is wrong with a decoded payload: the field (a path such as `conduits[3].nodes[1]`)
/// and why.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Invalid {
    pub field: String,
    pub problem: String,
}

impl Invalid {
    /// `field` is wrong because of `problem`.
    pub fn new(field: impl Into<String>, problem: impl Into<String>) -> Self {
        Invalid { field: field.into(), problem: problem.into() }
    }
}

/// Encodes `payload`, then atomically writes header and payload to `path`.
///
/// Postcard payloads are encoded twice, streaming: once into a hasher (for the header's length
/// and digest), then into the file, so that no copy of a large payload is ever held in memory.
/// The second encoding is not hashed again: it encodes the same value in memory, which cannot
/// come out different (a payload copied from elsewhere, [`write_artifact_with`], is).
pub fn write_artifact<P: Payload>(
    path: &Path,
    provenance: &Provenance,
    payload: &P,
) -> Result<Header, Error> {
    let encoding = P::STAGE.row().encoding;
    if encoding == Encoding::Postcard {
        return write_encoded::<P>(path, provenance, Recheck::No, |w| {
            let mut kept = KeepError { inner: Chunked::new(w), error: None };
            if let Err(e) = postcard::to_io(payload, &mut kept) {
                return Err(kept.error.take().unwrap_or_else(|| std::io::Error::other(e)));
            }
            kept.inner.finish().map(|_| ())
        });
    }
    let err = |e: String| Error::Encode { kind: P::STAGE.row().kind.into(), detail: e };
    let mut bytes = serde_json::to_vec_pretty(payload).map_err(|e| err(e.to_string()))?;
    bytes.push(b'\n');
    let header = header::<P>(provenance, bytes.len() as u64, hash::hex(&bytes));
    let line = serde_json::to_string(&header).map_err(|e| err(e.to_string()))?;
    atomic::write_with(path, |w| {
        w.write_all(JSON_OPEN)?;
        w.write_all(line.as_bytes())?;
        w.write_all(b",\n")?;
        w.write_all(JSON_PAYLOAD)?;
        w.write_all(&bytes)?;
        w.write_all(JSON_CLOSE)
    })
    .map_err(|source| Error::Write { path: path.to_path_buf(), source })?;
    Ok(header)
}

/// Atomically writes an artifact of `P`'s stage (a postcard one) whose payload bytes `encode`
/// writes, for a stage that never holds its payload in memory (the mesher copies its surfaces
/// from spill files). `encode` is called twice and must write the same bytes both times: once
/// into a hasher (the header, which comes first, holds the payload's length and digest), then
/// into the file, hashed again; a second pass that differs from the first is an error, not a
/// corrupted artifact. The bytes must be `P`'s postcard encoding: readers decode them as `P`.
pub fn write_artifact_with<P: Payload>(
    path: &Path,
    provenance: &Provenance,
    encode: impl FnMut(&mut dyn Write) -> std::io::Result<()>,
) -> Result<Header, Error> {
    write_encoded::<P>(path, provenance, Recheck::Yes, encode)
}

/// Whether the second encoding of a payload is hashed and compared with the first.
#[derive(PartialEq)]
enum Recheck {
    Yes,
    No,
}

/// [`write_artifact_with`], the second pass checked or not.
fn write_encoded<P: Payload>(
    path: &Path,
    provenance: &Provenance,
    recheck: Recheck,
    mut encode: impl FnMut(&mut dyn Write) -> std::io::Result<()>,
) -> Result<Header, Error> {
    let kind = || P::STAGE.row().kind.to_string();
    if P::STAGE.row().encoding != Encoding::Postcard {
        return Err(Error::Encode {
            kind: kind(),
            detail: "only postcard payloads are written streamed".into(),
        });
    }
    let write_error = |source| Error::Write { path: path.to_path_buf(), source };
    let mut first = HashSink { hasher: blake3::Hasher::new(), len: 0 };
    encode(&mut first).map_err(write_error)?;
    let header = header::<P>(provenance, first.len, first.hasher.finalize().to_hex().to_string());
    let line =
        serde_json::to_string(&header).map_err(|e| Error::Encode { kind: kind(), detail: e.to_string() })?;
    atomic::write_with(path, |w| {
        w.write_all(line.as_bytes())?;
        w.write_all(b"\n")?;
        if recheck == Recheck::No {
            return encode(w);
        }
        let mut second = Tee { inner: w, copy: HashSink { hasher: blake3::Hasher::new(), len: 0 } };
        encode(&mut second)?;
        let digest = second.copy.hasher.finalize().to_hex().to_string();
        if second.copy.len != header.payload_len || digest != header.payload_blake3 {
            return Err(std::io::Error::other(format!(
                "the {} payload's second encoding differs from the first ({} bytes, then {}): \
                 this is a bug in karstgen",
                kind(),
                header.payload_len,
                second.copy.len
            )));
        }
        Ok(())
    })
    .map_err(write_error)?;
    Ok(header)
}

/// The header of an artifact of `P`'s stage with a payload of `payload_len` bytes and digest
/// `payload_blake3`.
fn header<P: Payload>(provenance: &Provenance, payload_len: u64, payload_blake3: String) -> Header {
    Header {
        format: FORMAT.to_string(),
        kind: P::STAGE,
        schema: P::SCHEMA,
        producer: provenance.producer.clone(),
        encoding: P::STAGE.row().encoding,
        key: stage_key(
            P::STAGE,
            &provenance.producer,
            P::SCHEMA,
            &provenance.params,
            &provenance.frame,
            &provenance.inputs,
        ),
        inputs: provenance.inputs.clone(),
        params: provenance.params.clone(),
        origin: provenance.frame.origin,
        crs: provenance.frame.crs.clone(),
        payload_len,
        payload_blake3,
    }
}

/// Writes to `inner` and hashes what it writes into `copy`.
struct Tee<'w> {
    inner: &'w mut dyn Write,
    copy: HashSink,
}

impl Write for Tee<'_> {
    fn write(&mut self, buf: &[u8]) -> std::io::Result<usize> {
        let n = self.inner.write(buf)?;
        self.copy.write_all(&buf[..n])?;
        Ok(n)
    }

    fn flush(&mut self) -> std::io::Result<()> {
        self.inner.flush()
    }
}

/// Gathers the many small writes of postcard (one per number) into 64 KiB chunks before they
/// reach `inner`: hashing or writing each 8-byte field on its own cost about 1,500
/// instructions per sample in the sampling stage (blake3 and a `dyn Write` call per field).
struct Chunked<W: Write> {
    inner: W,
    buf: Vec<u8>,
}

impl<W: Write> Chunked<W> {
    const SIZE: usize = 1 << 16;

    fn new(inner: W) -> Self {
        Chunked { inner, buf: Vec::with_capacity(Self::SIZE) }
    }

    /// Writes what is left and returns the inner writer.
    fn finish(mut self) -> std::io::Result<W> {
        self.inner.write_all(&self.buf)?;
        self.buf.clear();
        Ok(self.inner)
    }
}

impl<W: Write> Write for Chunked<W> {
    #[inline]
    fn write(&mut self, buf: &[u8]) -> std::io::Result<usize> {
        self.write_all(buf)?;
        Ok(buf.len())
    }

    #[inline]
    fn write_all(&mut self, buf: &[u8]) -> std::io::Result<()> {
        if self.buf.len() + buf.len() > Self::SIZE {
            self.inner.write_all(&self.buf)?;
            self.buf.clear();
            if buf.len() >= Self::SIZE {
                return self.inner.write_all(buf);
            }
        }
        self.buf.extend_from_slice(buf);
        Ok(())
    }

    fn flush(&mut self) -> std::io::Result<()> {
        self.inner.write_all(&self.buf)?;
        self.buf.clear();
        self.inner.flush()
    }
}

/// Keeps the first I/O error of the writer it wraps: postcard reports any failed write as
/// "The serialize buffer is full", which would hide the real cause (a full disk).
struct KeepError<W: Write> {
    inner: W,
    error: Option<std::io::Error>,
}

impl<W: Write> KeepError<W> {
    fn keep(&mut self, result: std::io::Result<()>) -> std::io::Result<()> {
        result.map_err(|e| {
            let kind = e.kind();
            self.error.get_or_insert(e);
            std::io::Error::from(kind)
        })
    }
}

impl<W: Write> Write for KeepError<W> {
    fn write(&mut self, buf: &[u8]) -> std::io::Result<usize> {
        let result = self.inner.write_all(buf);
        self.keep(result).map(|_| buf.len())
    }

    fn write_all(&mut self, buf: &[u8]) -> std::io::Result<()> {
        let result = self.inner.write_all(buf);
        self.keep(result)
    }

    fn flush(&mut self) -> std::io::Result<()> {
        let result = self.inner.flush();
        self.keep(result)
    }
}

/// A writer that only hashes and counts what it is given.
struct HashSink {
    hasher: blake3::Hasher,
    len: u64,
}

impl Write for HashSink {
    fn write(&mut self, buf: &[u8]) -> std::io::Result<usize> {
        hash::update(&mut self.hasher, buf);
        self.len += buf.len() as u64;
        Ok(buf.len())
    }

    fn flush(&mut self) -> std::io::Result<()> {
        Ok(())
    }
}

/// Reads and checks only the header of an artifact of any kind.
pub fn read_header(path: &Path) -> Result<Header, Error> {
    let (file, _) = open(path)?;
    let mut reader = BufReader::new(file);
    read_header_from(path, &mut reader)
}

/// Reads an artifact of `P`'s stage, checking format, kind, schema, length and checksum, then
/// the payload's own consistency ([`Payload::validate`]).
pub fn read_artifact<P: Payload>(path: &Path) -> Result<(Header, P), Error> {
    let (file, file_len) = open(path)?;
    let mut reader = BufReader::new(file);
    let header = read_header_from(path, &mut reader)?;
    check_kind_and_schema::<P>(path, &header)?;
    let stage = P::STAGE.name().to_string();
    let length_error = |found: u64| Error::Length {
        path: path.into(),
        found,
        expected: header.payload_len,
        stage: stage.clone(),
    };
    // The header's length is checked against the file before anything is allocated for it.
    if header.payload_len > file_len {
        return Err(length_error(file_len));
    }
    if header.encoding == Encoding::Postcard {
        let mut bytes = PayloadReader::new(&mut reader, header.payload_len);
        if let Some(decoded) = P::read_streamed(&mut bytes) {
            let position = bytes.position();
            // The envelope's checks come first, as for a payload read whole: a corrupted file is a
            // length or checksum error whatever its decoding made of it.
            let (read, digest) =
                bytes.finish().map_err(|source| Error::Open { path: path.into(), source })?;
            if read != header.payload_len {
                return Err(length_error(read));
            }
            if digest != header.payload_blake3 {
                return Err(Error::Checksum { path: path.into(), stage });
            }
            let decoded = decoded.and_then(|value| read_to_the_end(value, position, header.payload_len));
            return Ok((header, validated(path, decoded.map_err(|e| decode_error::<P>(path, e))?)?));
        }
    }
    let mut payload = Vec::with_capacity(header.payload_len as usize);
    reader.read_to_end(&mut payload).map_err(|source| Error::Open { path: path.into(), source })?;
    if header.encoding == Encoding::Json {
        payload = json_payload(payload).ok_or_else(|| Error::NotAnArtifact {
            path: path.into(),
            detail: "a JSON artifact is {\"header\":…, \"payload\":…} on lines of their own".into(),
        })?;
    }
    if payload.len() as u64 != header.payload_len {
        return Err(length_error(payload.len() as u64));
    }
    if hash::hex(&payload) != header.payload_blake3 {
        return Err(Error::Checksum { path: path.into(), stage });
    }
    let value = decode_payload::<P>(path, header.encoding, &payload)?;
    Ok((header, value))
}

/// Decodes the payload bytes of an artifact of `P`'s stage (`path` names it in messages), then
/// checks it with [`Payload::validate`]: what [`read_artifact`] does once the envelope is
/// checked, and what the fuzz targets feed with arbitrary bytes.
pub fn decode_payload<P: Payload>(path: &Path, encoding: Encoding, bytes: &[u8]) -> Result<P, Error> {
    let decoded = match encoding {
        Encoding::Postcard => {
            let mut source = bytes;
            let len = bytes.len() as u64;
            let mut reader = PayloadReader::new(&mut source, len);
            match P::read_streamed(&mut reader) {
                Some(decoded) => decoded.and_then(|value| read_to_the_end(value, reader.position(), len)),
                None => postcard_whole(bytes),
            }
        }
        Encoding::Json => serde_json::from_slice(bytes).map_err(|e| DecodeError::Format(e.to_string())),
    };
    validated(path, decoded.map_err(|e| decode_error::<P>(path, e))?)
}

fn decode_error<P: Payload>(path: &Path, detail: DecodeError) -> Error {
    Error::Decode {
        path: path.into(),
        kind: P::STAGE.row().kind.into(),
        detail: detail.to_string(),
        stage: P::STAGE.name().into(),
    }
}

/// `value` once [`Payload::validate`] passes.
fn validated<P: Payload>(path: &Path, value: P) -> Result<P, Error> {
    value.validate().map_err(|invalid| Error::Invalid {
        path: path.into(),
        field: invalid.field,
        problem: invalid.problem,
        stage: P::STAGE.name().into(),
    })?;
    Ok(value)
}

/// Opens an artifact file: a regular file (a FIFO would block, a device never end).
fn open(path: &Path) -> Result<(fs::File, u64), Error> {
    crate::files::open_regular(path, u64::MAX).map_err(|source| Error::Open { path: path.into(), source })
}

/// Checks that an artifact's header is in `frame` (the scene's): an artifact made from the
/// same scene moved elsewhere, or in another CRS, is not an input of this run.
pub fn check_frame(path: &Path, header: &Header, expected: &Frame) -> Result<(), Error> {
    if header.origin == expected.origin && header.crs == expected.crs {
        return Ok(());
    }
    let frame = |origin: [f64; 3], crs: &Option<String>| {
        format!("origin {origin:?} ({})", crs.as_deref().unwrap_or("no CRS"))
    };
    Err(Error::Frame {
        path: path.into(),
        found: frame(header.origin, &header.crs),
        expected: frame(expected.origin, &expected.crs),
        stage: header.kind.name().into(),
    })
}

/// The payload's bytes in what follows a JSON artifact's first line: `"payload":` on a line of
/// its own, the payload, then `}` on the last line.
fn json_payload(mut rest: Vec<u8>) -> Option<Vec<u8>> {
    let end = rest.strip_suffix(JSON_CLOSE)?.len();
    rest.truncate(end);
    rest.starts_with(JSON_PAYLOAD).then(|| rest.split_off(JSON_PAYLOAD.len()))
}

/// Reads the header line: the whole first line of a bulk artifact, or the `header` field on
/// the first line of a JSON artifact.
fn read_header_from(path: &Path, reader: &mut impl BufRead) -> Result<Header, Error> {
    let mut line = Vec::new();
    reader
        .take(MAX_HEADER_LEN)
        .read_until(b'\n', &mut line)
        .map_err(|source| Error::Open { path: path.into(), source })?;
    let not_ours = |detail: String| Error::NotAnArtifact { path: path.into(), detail };
    let Some(line) = line.strip_suffix(b"\n") else {
        return Err(not_ours("no header line".into()));
    };
    let json = line.strip_prefix(JSON_OPEN).and_then(|rest| rest.strip_suffix(b","));
    let text =
        std::str::from_utf8(json.unwrap_or(line)).map_err(|_| not_ours("header is not UTF-8".into()))?;
    let value: serde_json::Value =
        serde_json::from_str(text).map_err(|e| not_ours(format!("header is not JSON: {e}")))?;
    if value.get("format").and_then(|f| f.as_str()) != Some(FORMAT) {
        return Err(not_ours(format!("header has no \"format\": \"{FORMAT}\"")));
    }
    let header: Header = serde_json::from_value(value).map_err(|e| not_ours(format!("bad header: {e}")))?;
    let layout_is_json = json.is_some();
    if layout_is_json != (header.encoding == Encoding::Json) {
        return Err(not_ours("the header's encoding does not match the file's layout".into()));
    }
    Ok(header)
}

fn check_kind_and_schema<P: Payload>(path: &Path, header: &Header) -> Result<(), Error> {
    if header.kind != P::STAGE {
        return Err(Error::WrongKind {
            path: path.into(),
            found: header.kind.row().kind.into(),
            expected: P::STAGE.row().kind.into(),
        });
    }
    if header.schema != P::SCHEMA {
        return Err(Error::Schema {
            path: path.into(),
            kind: P::STAGE.row().kind.into(),
            found: header.schema,
            expected: P::SCHEMA,
            stage: P::STAGE.name().into(),
        });
    }
    if header.encoding != P::STAGE.row().encoding {
        return Err(Error::NotAnArtifact {
            path: path.into(),
            detail: format!("a {} artifact is never {:?}-encoded", P::STAGE.row().kind, header.encoding),
        });
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use karst_testkit::Scratch;
    use std::path::PathBuf;

    #[derive(Debug, PartialEq, Serialize, Deserialize)]
    struct Points(Vec<[f64; 3]>);
    impl Payload for Points {
        const STAGE: StageId = StageId::Sampling;
        const SCHEMA: u32 = 7;
    }

    #[derive(Debug, PartialEq, Serialize, Deserialize)]
    struct Other(u32);
    impl Payload for Other {
        const STAGE: StageId = StageId::Hydro;
        const SCHEMA: u32 = 1;
    }

    fn provenance() -> Provenance {
        Provenance { producer: "test 0".into(), inputs: vec![], params: "p".into(), frame: Frame::default() }
    }

    /// A file `name` in a fresh scratch folder, which is removed when the test passes.
    fn scratch(name: &str) -> (Scratch, PathBuf) {
        let dir = karst_testkit::scratch(&format!("envelope-{name}"));
        let path = dir.join(name);
        (dir, path)
    }

    #[test]
    fn round_trip() {
        let (_dir, path) = scratch("rt.bin");
        let pts = Points(vec![[1.0, 2.0, 3.5], [-4.0, 0.0, 1e9]]);
        let header = write_artifact(&path, &provenance(), &pts).unwrap();
        let (read_back_header, back) = read_artifact::<Points>(&path).unwrap();
        assert_eq!(back, pts);
        assert_eq!(read_back_header, header);
        assert_eq!(read_header(&path).unwrap(), header);
    }

    #[test]
    fn streamed_payload_is_the_encoded_payload() {
        let (_dir, path) = scratch("stream.bin");
        let pts = Points((0..5000).map(|i| [i as f64, 0.5 * i as f64, -1.25]).collect());
        let header = write_artifact(&path, &provenance(), &pts).unwrap();
        let bytes = fs::read(&path).unwrap();
        let payload = &bytes[bytes.iter().position(|b| *b == b'\n').unwrap() + 1..];
        assert_eq!(payload, postcard::to_stdvec(&pts).unwrap().as_slice());
        assert_eq!(header.payload_len, payload.len() as u64);
        assert_eq!(header.payload_blake3, hash::hex(payload));
    }

    #[test]
    fn a_payload_written_by_its_encoder_is_the_artifact_of_the_payload() {
        let ((_with, streamed), (_whole, whole)) = (scratch("with.bin"), scratch("whole.bin"));
        let pts = Points((0..3000).map(|i| [i as f64, -0.5, 1e3]).collect());
        let bytes = postcard::to_stdvec(&pts).unwrap();
        // Written in uneven pieces, as a stage copying from its spill files would.
        let header = write_artifact_with::<Points>(&streamed, &provenance(), |w| {
            bytes.chunks(777).try_for_each(|piece| w.write_all(piece))
        })
        .unwrap();
        assert_eq!(header, write_artifact(&whole, &provenance(), &pts).unwrap());
        assert_eq!(fs::read(&streamed).unwrap(), fs::read(&whole).unwrap());
        assert_eq!(read_artifact::<Points>(&streamed).unwrap().1, pts);
        // An encoder that writes other bytes the second time: refused, the old file kept.
        let mut calls = 0;
        let err = write_artifact_with::<Points>(&streamed, &provenance(), |w| {
            calls += 1;
            w.write_all(&bytes[..bytes.len() - calls])
        })
        .unwrap_err();
        let cause = std::error::Error::source(&err).map(|e| e.to_string()).unwrap_or_default();
        assert!(cause.contains("second encoding differs"), "{err}: {cause}");
        assert_eq!(fs::read(&streamed).unwrap(), fs::read(&whole).unwrap());
        // A JSON stage's payload is not written streamed.
        let (_dir, other) = scratch("other.json");
        assert!(write_artifact_with::<Other>(&other, &provenance(), |_| Ok(())).is_err());
    }

    #[test]
    fn flipped_byte_is_a_checksum_error_naming_the_file() {
        let (_dir, path) = scratch("flip.bin");
        write_artifact(&path, &provenance(), &Points(vec![[1.0, 2.0, 3.0]; 10])).unwrap();
        let mut bytes = fs::read(&path).unwrap();
        let last = bytes.len() - 5;
        bytes[last] ^= 0x40;
        fs::write(&path, bytes).unwrap();
        let err = read_artifact::<Points>(&path).unwrap_err();
        assert!(matches!(err, Error::Checksum { .. }), "{err}");
        assert!(err.to_string().contains("flip.bin"));
        assert!(err.to_string().contains("--from sampling"));
    }

    #[test]
    fn truncated_wrong_kind_and_garbage_are_rejected() {
        let (_dir, path) = scratch("trunc.bin");
        write_artifact(&path, &provenance(), &Points(vec![[1.0, 2.0, 3.0]; 10])).unwrap();
        let bytes = fs::read(&path).unwrap();
        fs::write(&path, &bytes[..bytes.len() - 3]).unwrap();
        assert!(matches!(read_artifact::<Points>(&path), Err(Error::Length { .. })));

        write_artifact(&path, &provenance(), &Points(vec![])).unwrap();
        assert!(matches!(read_artifact::<Other>(&path), Err(Error::WrongKind { .. })));

        fs::write(&path, b"\x00\x01garbage").unwrap();
        assert!(matches!(read_artifact::<Points>(&path), Err(Error::NotAnArtifact { .. })));
        fs::write(&path, b"{\"format\":\"something-else\"}\n").unwrap();
        assert!(matches!(read_header(&path), Err(Error::NotAnArtifact { .. })));
    }

    #[test]
    fn json_artifacts_are_one_json_document() {
        let (_dir, path) = scratch("doc.json");
        let value = Other(42);
        let header = write_artifact(&path, &provenance(), &value).unwrap();
        let whole: serde_json::Value = serde_json::from_slice(&fs::read(&path).unwrap()).unwrap();
        assert_eq!(whole["payload"], serde_json::json!(42));
        assert_eq!(whole["header"]["kind"], "hydro");
        assert_eq!(read_header(&path).unwrap(), header);
        assert_eq!(read_artifact::<Other>(&path).unwrap().1, value);
        // The checksum covers the payload's bytes: an edit inside it is caught.
        let text = fs::read_to_string(&path).unwrap().replace("42", "43");
        fs::write(&path, text).unwrap();
        assert!(matches!(read_artifact::<Other>(&path), Err(Error::Checksum { .. })));
    }

    #[test]
    fn a_length_beyond_the_file_is_refused_before_allocating() {
        let (_dir, path) = scratch("huge.bin");
        write_artifact(&path, &provenance(), &Points(vec![[1.0, 2.0, 3.0]])).unwrap();
        let text = fs::read(&path).unwrap();
        let line_end = text.iter().position(|b| *b == b'\n').unwrap();
        let header = String::from_utf8(text[..line_end].to_vec()).unwrap();
        let len = read_header(&path).unwrap().payload_len;
        let forged = header.replace(&format!("\"payload_len\":{len}"), "\"payload_len\":1099511627776");
        fs::write(&path, [forged.as_bytes(), &text[line_end..]].concat()).unwrap();
        assert!(matches!(read_artifact::<Points>(&path), Err(Error::Length { .. })));
    }

    #[test]
    fn invalid_payloads_name_the_field() {
        #[derive(Debug, PartialEq, Serialize, Deserialize)]
        struct Positive(f64);
        impl Payload for Positive {
            const STAGE: StageId = StageId::Metrics;
            const SCHEMA: u32 = 1;
            fn validate(&self) -> Result<(), Invalid> {
                if self.0 > 0.0 {
                    Ok(())
                } else {
                    Err(Invalid::new("value", format!("{} is not positive", self.0)))
                }
            }
        }
        let (_dir, path) = scratch("invalid.json");
        write_artifact(&path, &provenance(), &Positive(-1.0)).unwrap();
        let err = read_artifact::<Positive>(&path).unwrap_err();
        assert!(matches!(err, Error::Invalid { .. }), "{err}");
        assert!(err.to_string().contains("value: -1 is not positive"), "{err}");
    }

    #[test]
    fn a_full_disk_is_reported_as_such() {
        // A writer that fails like a full disk after some bytes: the error postcard returns
        // must not hide it.
        struct Full(usize);
        impl Write for Full {
            fn write(&mut self, buf: &[u8]) -> std::io::Result<usize> {
                if self.0 < buf.len() {
                    return Err(std::io::Error::from(std::io::ErrorKind::StorageFull));
                }
                self.0 -= buf.len();
                Ok(buf.len())
            }
            fn flush(&mut self) -> std::io::Result<()> {
                Ok(())
            }
        }
        let points = Points((0..100_000).map(|i| [i as f64; 3]).collect());
        let mut kept = KeepError { inner: Chunked::new(Full(100_000)), error: None };
        let Err(err) = postcard::to_io(&points, &mut kept) else { panic!("the writer is full") };
        assert!(err.to_string().contains("buffer is full"), "postcard hides the cause: {err}");
        let kept = kept.error.expect("the real error is kept");
        assert_eq!(kept.kind(), std::io::ErrorKind::StorageFull);
        let message = Error::Write { path: "out/samples.bin".into(), source: kept }.to_string();
        assert_eq!(message, "out/samples.bin: cannot write: the disk is full");
    }

    #[test]
    fn the_header_records_the_frame_and_another_frame_is_refused() {
        let (_dir, path) = scratch("frame.bin");
        let lambert = Frame { origin: [651000.0, 6862000.0, 250.0], crs: Some("EPSG:2154".into()) };
        let header =
            write_artifact(&path, &Provenance { frame: lambert.clone(), ..provenance() }, &Points(vec![]))
                .unwrap();
        assert_eq!(read_header(&path).unwrap().frame(), lambert);
        assert_ne!(header.key, write_artifact(&path, &provenance(), &Points(vec![])).unwrap().key);
        assert!(check_frame(&path, &header, &lambert).is_ok());
        let err = check_frame(&path, &header, &Frame::default()).unwrap_err().to_string();
        assert!(err.contains("origin [651000.0, 6862000.0, 250.0] (EPSG:2154)"), "{err}");
        assert!(err.contains("origin [0.0, 0.0, 0.0] (no CRS)") && err.contains("--from sampling"), "{err}");
    }

    #[test]
    fn other_schema_says_what_to_rerun() {
        let (_dir, path) = scratch("schema.bin");
        write_artifact(&path, &provenance(), &Points(vec![])).unwrap();
        let text = fs::read_to_string(&path).unwrap().replacen("\"schema\":7", "\"schema\":6", 1);
        fs::write(&path, text).unwrap();
        let err = read_artifact::<Points>(&path).unwrap_err();
        assert!(err.to_string().contains("schema 6, this build reads schema 7"), "{err}");
    }
}
