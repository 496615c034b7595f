//! Hash tables keyed by a grid cell's integer key: the sparse grids of the rock pieces
//! ([`crate::detail::rock`]) and of the mesher's sphere groups look one key up per query, so the
//! key is hashed in one step, with no per-process seed (nothing depends on a table's order).

use std::collections::HashMap;
use std::hash::{BuildHasherDefault, Hasher};

/// A table from grid keys to `V`.
pub type KeyMap<V> = HashMap<u64, V, BuildHasherDefault<KeyHasher>>;

/// Fibonacci hashing of a `u64` key: the multiplication spreads the keys' low bits.
#[derive(Default)]
pub struct KeyHasher(u64);

impl Hasher for KeyHasher {
    fn finish(&self) -> u64 {
        self.0
    }

    fn write(&mut self, bytes: &[u8]) {
        for &b in bytes {
            self.write_u64(b as u64);
        }
    }

    fn write_u64(&mut self, key: u64) {
        self.0 = (self.0 ^ key).wrapping_mul(0x9E37_79B9_7F4A_7C15).rotate_left(29);
    }
}
