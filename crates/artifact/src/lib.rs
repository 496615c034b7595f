//! The versioned artifact envelope that joins karstgen's stages, and the stage table.
//!
//! Every artifact file holds a [`Header`] and the payload: bulk artifacts as one line of JSON
//! followed by the postcard payload, JSON artifacts as one JSON document
//! `{"header": …, "payload": …}` ([`envelope`]). The header
//! says what the file is (`kind`, `schema`, `encoding`), who wrote it (`producer`), what it was
//! made from (`inputs`, `params`), where its coordinates lie in the world (`origin`, `crs`:
//! [`frame`]) and how to check it (`payload_len`, `payload_blake3`). The
//! `key` decides staleness: `cargo xtask run` skips a stage whose artifact's key equals the key
//! it would write now (see [`stages::stage_key`]).
//!
//! Writing is atomic ([`atomic`]): a killed stage leaves the old artifact or none, never a torn
//! one. Reading checks format, kind, schema, length and checksum and says what to do when one
//! fails.

pub mod atomic;
pub mod bulk;
pub mod check;
pub mod envelope;
pub mod error;
pub mod files;
pub mod frame;
pub mod hash;
pub mod lock;
pub mod stages;
pub mod stream;
mod whole;

pub use envelope::{
    Header, InputRef, Invalid, Payload, Provenance, check_frame, decode_payload, read_artifact, read_header,
    write_artifact, write_artifact_with,
};
pub use error::{DecodeError, Error};
pub use frame::Frame;
pub use lock::{OutputLock, lock_output};
pub use stages::{Encoding, StageId, StageRow};
pub use stream::PayloadReader;
