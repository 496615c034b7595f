//! Payloads decoded to their last byte: postcard stops at a payload's last field, so bytes
//! left over are how a wrong length (inside the payload or the header's) shows. Shared by the
//! whole-file reader (envelope.rs) and the streamed one (stream.rs).

use serde::de::DeserializeOwned;

use crate::error::DecodeError;

/// Decodes postcard `bytes` to their last byte: bytes left over mean that a length inside
/// the payload, or the header's, is wrong (postcard alone stops at the last field).
pub(crate) fn postcard_whole<T: DeserializeOwned>(bytes: &[u8]) -> Result<T, DecodeError> {
    let (value, rest) = postcard::take_from_bytes(bytes).map_err(|e| DecodeError::Format(e.to_string()))?;
    read_to_the_end(value, (bytes.len() - rest.len()) as u64, bytes.len() as u64)
}

/// `value` when its fields ended at byte `end` of a payload of `len` bytes: its last byte.
pub(crate) fn read_to_the_end<T>(value: T, end: u64, len: u64) -> Result<T, DecodeError> {
    if end != len {
        return Err(DecodeError::Leftover { end, len });
    }
    Ok(value)
}
