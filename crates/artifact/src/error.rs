//! Errors of the artifact layer. Every message names the file; I/O errors keep the operating
//! system's error as their source, so that the whole chain is printed ("FILE: cannot read: No
//! such file or directory").

use std::path::PathBuf;

/// What can go wrong when reading or writing an artifact. Every message names the file.
#[derive(Debug, thiserror::Error)]
pub enum Error {
    #[error("{path}: cannot read")]
    Open { path: PathBuf, source: std::io::Error },
    #[error("{path}: cannot write{}", disk_full(source))]
    Write { path: PathBuf, source: std::io::Error },
    #[error("{path}: not a karstgen artifact ({detail})")]
    NotAnArtifact { path: PathBuf, detail: String },
    #[error("{path}: is a {found} artifact, expected {expected}")]
    WrongKind { path: PathBuf, found: String, expected: String },
    #[error(
        "{path}: written by {kind} schema {found}, this build reads schema {expected}: \
         rerun the pipeline from {stage} (`karstgen run SCENE --from {stage}`)"
    )]
    Schema { path: PathBuf, kind: String, found: u32, expected: u32, stage: String },
    #[error(
        "{path}: payload is {found} bytes, the header says {expected} (truncated file?): \
         rerun the pipeline from {stage} (`karstgen run SCENE --from {stage}`)"
    )]
    Length { path: PathBuf, found: u64, expected: u64, stage: String },
    #[error(
        "{path}: payload checksum mismatch (the file is corrupted): \
         rerun the pipeline from {stage} (`karstgen run SCENE --from {stage}`)"
    )]
    Checksum { path: PathBuf, stage: String },
    #[error(
        "{path}: cannot decode the {kind} payload ({detail}): rerun the pipeline from {stage} (`karstgen run SCENE --from {stage}`)"
    )]
    Decode { path: PathBuf, kind: String, detail: String, stage: String },
    #[error(
        "{path}: {field}: {problem}: rerun the pipeline from {stage} (`karstgen run SCENE --from {stage}`)"
    )]
    Invalid { path: PathBuf, field: String, problem: String, stage: String },
    #[error(
        "{path}: its coordinates are relative to {found}, the scene's to {expected}: \
         rerun the pipeline from {stage} (`karstgen run SCENE --from {stage}`)"
    )]
    Frame { path: PathBuf, found: String, expected: String, stage: String },
    #[error("cannot encode the {kind} payload: {detail}")]
    Encode { kind: String, detail: String },
    #[error("another run is writing to {dir}: wait for it to finish, or use another --out")]
    Busy { dir: PathBuf },
}

/// Says so when a write failed because the disk is full (the OS error follows as the source).
fn disk_full(source: &std::io::Error) -> &'static str {
    if source.kind() == std::io::ErrorKind::StorageFull { ": the disk is full" } else { "" }
}

impl Error {
    /// True when the error comes from a file the user gave us (exit code 2), false when
    /// karstgen or the machine failed (exit code 1).
    pub fn is_bad_input(&self) -> bool {
        !matches!(self, Error::Write { .. } | Error::Encode { .. } | Error::Busy { .. })
    }
}

/// Why a payload's bytes do not decode (the detail of [`Error::Decode`]).
#[derive(Debug, thiserror::Error, PartialEq)]
pub enum DecodeError {
    #[error("{wanted} bytes wanted, {left} left in the payload")]
    Short { wanted: u64, left: u64 },
    #[error("after {at} bytes: {reason}")]
    Io { at: u64, reason: String },
    #[error("the payload ends after {0} bytes")]
    Truncated(u64),
    #[error("a varint longer than 10 bytes")]
    LongVarint,
    #[error("a length of {length} with {left} bytes left in the payload")]
    Length { length: u64, left: u64 },
    #[error("a bulk array of {width}-byte numbers has {bytes} bytes")]
    BulkWidth { width: usize, bytes: usize },
    /// postcard's or serde_json's reason.
    #[error("{0}")]
    Format(String),
    #[error(
        "the payload's fields end at byte {end} of its {len}: a length inside it or the header's payload_len is wrong"
    )]
    Leftover { end: u64, len: u64 },
    /// A field that decodes but holds a value its type cannot (a payload's own check).
    #[error("{field}: {problem}")]
    Field { field: String, problem: String },
}
