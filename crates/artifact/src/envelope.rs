//! The artifact file format: a one-line JSON [`Header`] then the payload.
//!
//! Bulk payloads (samples, costgraph, sdf, mesh) are encoded with postcard (a maintained serde
//! codec with a stable, documented wire format; see the README for the measurement that chose
//! it over bincode 2); small ones (skeleton, hydro, metrics) are pretty JSON so that a review or
//! CI diff is readable.

use std::fs;
use std::io::{BufRead, BufReader, Read, Write};
use std::path::Path;

use serde::de::DeserializeOwned;
use serde::{Deserialize, Serialize};

use crate::error::Error;
use crate::{atomic, hash};

/// The value of the header's `format` field.
pub const FORMAT: &str = "karstgen-artifact";

/// Longest header line accepted; anything longer is not one of ours.
const MAX_HEADER_LEN: u64 = 64 * 1024;

/// The kinds of artifact, one per stage.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Kind {
    Samples,
    Costgraph,
    Skeleton,
    Hydro,
    Sdf,
    Mesh,
    Metrics,
}

impl Kind {
    /// Lowercase name, as in the header.
    pub fn name(self) -> &'static str {
        match self {
            Kind::Samples => "samples",
            Kind::Costgraph => "costgraph",
            Kind::Skeleton => "skeleton",
            Kind::Hydro => "hydro",
            Kind::Sdf => "sdf",
            Kind::Mesh => "mesh",
            Kind::Metrics => "metrics",
        }
    }

    /// How this kind's payload is encoded.
    pub fn encoding(self) -> Encoding {
        match self {
            Kind::Samples | Kind::Costgraph | Kind::Sdf | Kind::Mesh => Encoding::Postcard,
            Kind::Skeleton | Kind::Hydro | Kind::Metrics => Encoding::Json,
        }
    }

    /// The stage that writes this kind (named in "rerun" advice).
    pub fn stage_name(self) -> &'static str {
        crate::pipeline::Stage::of_kind(self).name()
    }
}

/// Payload encodings.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
pub enum Encoding {
    /// postcard 1.x wire format.
    #[serde(rename = "postcard-1")]
    Postcard,
    /// Pretty-printed JSON.
    #[serde(rename = "json")]
    Json,
}

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
#[derive(Debug, Clone, PartialEq, Eq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Header {
    pub format: String,
    pub kind: Kind,
    pub schema: u32,
    pub producer: String,
    pub encoding: Encoding,
    pub key: String,
    pub inputs: Vec<InputRef>,
    pub params: String,
    pub payload_len: u64,
    pub payload_blake3: String,
}

/// Where an artifact comes from: who made it, from which inputs and scene sections. The key
/// is derived from it and the payload's schema when the artifact is written.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Provenance {
    pub producer: String,
    pub inputs: Vec<InputRef>,
    pub params: String,
}

/// A type that is the payload of one kind of artifact.
pub trait Payload: Serialize + DeserializeOwned {
    /// The artifact kind.
    const KIND: Kind;
    /// Bumped on every change of the payload's layout or meaning.
    const SCHEMA: u32;
}

/// Encodes `payload`, then atomically writes header and payload to `path`.
///
/// Postcard payloads are encoded twice, streaming: once into a hasher (for the header's length
/// and digest), then into the file, so that no copy of a large payload is ever held in memory.
pub fn write_artifact<P: Payload>(
    path: &Path,
    provenance: &Provenance,
    payload: &P,
) -> Result<Header, Error> {
    let err = |e: String| Error::Encode { kind: P::KIND.name().into(), detail: e };
    let (bytes, payload_len, payload_blake3) = match P::KIND.encoding() {
        Encoding::Postcard => {
            let mut sink = Chunked::new(HashSink { hasher: blake3::Hasher::new(), len: 0 });
            postcard::to_io(payload, &mut sink).map_err(|e| err(e.to_string()))?;
            let sink = sink.finish().map_err(|e| err(e.to_string()))?;
            (None, sink.len, sink.hasher.finalize().to_hex().to_string())
        }
        Encoding::Json => {
            let bytes = encode(payload)?;
            let (len, digest) = (bytes.len() as u64, hash::hex(&bytes));
            (Some(bytes), len, digest)
        }
    };
    let stage = crate::pipeline::Stage::of_kind(P::KIND);
    let key = crate::pipeline::stage_key(
        stage,
        &provenance.producer,
        P::SCHEMA,
        &provenance.params,
        &provenance.inputs,
    );
    let header = Header {
        format: FORMAT.to_string(),
        kind: P::KIND,
        schema: P::SCHEMA,
        producer: provenance.producer.clone(),
        encoding: P::KIND.encoding(),
        key,
        inputs: provenance.inputs.clone(),
        params: provenance.params.clone(),
        payload_len,
        payload_blake3,
    };
    let line = serde_json::to_string(&header).map_err(|e| err(e.to_string()))?;
    atomic::write_with(path, |w| {
        w.write_all(line.as_bytes())?;
        w.write_all(b"\n")?;
        match &bytes {
            Some(bytes) => w.write_all(bytes),
            None => {
                let mut chunked = Chunked::new(w);
                postcard::to_io(payload, &mut chunked).map_err(std::io::Error::other)?;
                chunked.finish().map(|_| ())
            }
        }
    })
    .map_err(|source| Error::Write { path: path.to_path_buf(), source })?;
    Ok(header)
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
    let file = fs::File::open(path).map_err(|source| Error::Open { path: path.into(), source })?;
    let mut reader = BufReader::new(file);
    read_header_from(path, &mut reader)
}

/// Reads an artifact of kind `P::KIND`, checking format, kind, schema, length and checksum.
pub fn read_artifact<P: Payload>(path: &Path) -> Result<(Header, P), Error> {
    let file = fs::File::open(path).map_err(|source| Error::Open { path: path.into(), source })?;
    let mut reader = BufReader::new(file);
    let header = read_header_from(path, &mut reader)?;
    check_kind_and_schema::<P>(path, &header)?;
    let mut payload = Vec::with_capacity(header.payload_len.min(1 << 32) as usize);
    reader.read_to_end(&mut payload).map_err(|source| Error::Open { path: path.into(), source })?;
    let stage = P::KIND.stage_name().to_string();
    if payload.len() as u64 != header.payload_len {
        return Err(Error::Length {
            path: path.into(),
            found: payload.len() as u64,
            expected: header.payload_len,
            stage,
        });
    }
    if hash::hex(&payload) != header.payload_blake3 {
        return Err(Error::Checksum { path: path.into(), stage });
    }
    let value = decode::<P>(&payload).map_err(|detail| Error::Decode {
        path: path.into(),
        kind: P::KIND.name().into(),
        detail,
        stage,
    })?;
    Ok((header, value))
}

fn read_header_from(path: &Path, reader: &mut impl BufRead) -> Result<Header, Error> {
    let mut line = Vec::new();
    reader
        .take(MAX_HEADER_LEN)
        .read_until(b'\n', &mut line)
        .map_err(|source| Error::Open { path: path.into(), source })?;
    let not_ours = |detail: String| Error::NotAnArtifact { path: path.into(), detail };
    if line.last() != Some(&b'\n') {
        return Err(not_ours("no header line".into()));
    }
    let text = std::str::from_utf8(&line).map_err(|_| not_ours("header is not UTF-8".into()))?;
    let value: serde_json::Value =
        serde_json::from_str(text).map_err(|e| not_ours(format!("header is not JSON: {e}")))?;
    if value.get("format").and_then(|f| f.as_str()) != Some(FORMAT) {
        return Err(not_ours(format!("header has no \"format\": \"{FORMAT}\"")));
    }
    serde_json::from_value(value).map_err(|e| not_ours(format!("bad header: {e}")))
}

fn check_kind_and_schema<P: Payload>(path: &Path, header: &Header) -> Result<(), Error> {
    if header.kind != P::KIND {
        return Err(Error::WrongKind {
            path: path.into(),
            found: header.kind.name().into(),
            expected: P::KIND.name().into(),
        });
    }
    if header.schema != P::SCHEMA {
        return Err(Error::Schema {
            path: path.into(),
            kind: P::KIND.name().into(),
            found: header.schema,
            expected: P::SCHEMA,
            stage: P::KIND.stage_name().into(),
        });
    }
    Ok(())
}

fn encode<P: Payload>(payload: &P) -> Result<Vec<u8>, Error> {
    let err = |e: String| Error::Encode { kind: P::KIND.name().into(), detail: e };
    match P::KIND.encoding() {
        Encoding::Postcard => postcard::to_stdvec(payload).map_err(|e| err(e.to_string())),
        Encoding::Json => {
            let mut bytes = serde_json::to_vec_pretty(payload).map_err(|e| err(e.to_string()))?;
            bytes.push(b'\n');
            Ok(bytes)
        }
    }
}

fn decode<P: Payload>(bytes: &[u8]) -> Result<P, String> {
    match P::KIND.encoding() {
        Encoding::Postcard => postcard::from_bytes(bytes).map_err(|e| e.to_string()),
        Encoding::Json => serde_json::from_slice(bytes).map_err(|e| e.to_string()),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[derive(Debug, PartialEq, Serialize, Deserialize)]
    struct Points(Vec<[f64; 3]>);
    impl Payload for Points {
        const KIND: Kind = Kind::Samples;
        const SCHEMA: u32 = 7;
    }

    #[derive(Debug, PartialEq, Serialize, Deserialize)]
    struct Other(u32);
    impl Payload for Other {
        const KIND: Kind = Kind::Hydro;
        const SCHEMA: u32 = 1;
    }

    fn provenance() -> Provenance {
        Provenance { producer: "test 0".into(), inputs: vec![], params: "p".into() }
    }

    fn scratch(name: &str) -> std::path::PathBuf {
        let dir = std::env::temp_dir().join(format!("karst-envelope-{}", std::process::id()));
        fs::create_dir_all(&dir).unwrap();
        dir.join(name)
    }

    #[test]
    fn round_trip() {
        let path = scratch("rt.bin");
        let pts = Points(vec![[1.0, 2.0, 3.5], [-4.0, 0.0, 1e9]]);
        let header = write_artifact(&path, &provenance(), &pts).unwrap();
        let (read_back_header, back) = read_artifact::<Points>(&path).unwrap();
        assert_eq!(back, pts);
        assert_eq!(read_back_header, header);
        assert_eq!(read_header(&path).unwrap(), header);
    }

    #[test]
    fn streamed_payload_is_the_encoded_payload() {
        let path = scratch("stream.bin");
        let pts = Points((0..5000).map(|i| [i as f64, 0.5 * i as f64, -1.25]).collect());
        let header = write_artifact(&path, &provenance(), &pts).unwrap();
        let bytes = fs::read(&path).unwrap();
        let payload = &bytes[bytes.iter().position(|b| *b == b'\n').unwrap() + 1..];
        assert_eq!(payload, postcard::to_stdvec(&pts).unwrap().as_slice());
        assert_eq!(header.payload_len, payload.len() as u64);
        assert_eq!(header.payload_blake3, hash::hex(payload));
    }

    #[test]
    fn flipped_byte_is_a_checksum_error_naming_the_file() {
        let path = scratch("flip.bin");
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
        let path = scratch("trunc.bin");
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
    fn other_schema_says_what_to_rerun() {
        let path = scratch("schema.bin");
        write_artifact(&path, &provenance(), &Points(vec![])).unwrap();
        let text = fs::read_to_string(&path).unwrap().replacen("\"schema\":7", "\"schema\":6", 1);
        fs::write(&path, text).unwrap();
        let err = read_artifact::<Points>(&path).unwrap_err();
        assert!(err.to_string().contains("schema 6, this build reads schema 7"), "{err}");
    }
}
