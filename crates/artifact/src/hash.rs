//! BLAKE3 hashing helpers: every hash in karstgen is a lowercase hex BLAKE3 digest.

/// Hex digest of `bytes`.
pub fn hex(bytes: &[u8]) -> String {
    blake3::hash(bytes).to_hex().to_string()
}

/// Hex digest of several byte strings, each prefixed by its length so that
/// `["ab", "c"]` and `["a", "bc"]` hash differently.
pub fn hex_of_parts<'a>(parts: impl IntoIterator<Item = &'a [u8]>) -> String {
    let mut hasher = blake3::Hasher::new();
    for part in parts {
        hasher.update(&(part.len() as u64).to_le_bytes());
        hasher.update(part);
    }
    hasher.finalize().to_hex().to_string()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn parts_are_length_prefixed() {
        assert_ne!(hex_of_parts([b"ab".as_slice(), b"c"]), hex_of_parts([b"a".as_slice(), b"bc"]));
        assert_eq!(hex(b"x").len(), 64);
    }
}
