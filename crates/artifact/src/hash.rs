//! BLAKE3 hashing helpers: every hash in karstgen is a lowercase hex BLAKE3 digest.

/// Inputs from this size on are hashed on every core: BLAKE3 is a tree of 1 KiB chunks, so
/// the digest is the same whatever the number of threads (artifact payloads of tens of MB are
/// checked on every read and hashed on every write).
const PARALLEL_FROM: usize = 1 << 20;

/// Hex digest of `bytes`.
pub fn hex(bytes: &[u8]) -> String {
    let mut hasher = blake3::Hasher::new();
    update(&mut hasher, bytes);
    hasher.finalize().to_hex().to_string()
}

/// Adds `bytes` to `hasher`, on every core when they are large.
pub fn update(hasher: &mut blake3::Hasher, bytes: &[u8]) {
    if bytes.len() >= PARALLEL_FROM {
        hasher.update_rayon(bytes);
    } else {
        hasher.update(bytes);
    }
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
