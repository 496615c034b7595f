//! Bulk arrays in binary artifacts as fixed-width little-endian bytes.
//!
//! A bulk artifact (the cost graph's rows and costs, millions of numbers) encoded one serde
//! element at a time costs a varint or a 4-byte write per number, twice (the envelope hashes
//! the payload, then writes it), and a visitor call per number to decode. Marked with
//! `#[serde(with = "karst_artifact::bulk")]`, a `Vec<u32>`, `Vec<f32>`, `Vec<u64>` or `Vec<f64>`
//! field is one byte string instead: in postcard 1 its length as a varint, then the raw
//! little-endian values, written straight from the vector's memory (on little-endian machines)
//! and read back with one copy. The payload stays a postcard-1 payload, under the envelope's
//! length and BLAKE3 checks, so nothing about the envelope changes.
//!
//! Human-readable formats (the JSON of `inspect --json`, `cargo xtask diff`) still see plain
//! sequences of numbers.

use std::marker::PhantomData;

use serde::de::{SeqAccess, Visitor};
use serde::{Deserialize, Deserializer, Serialize, Serializer};

/// A number stored in a bulk array: fixed width, little-endian.
pub trait Element: Copy + Serialize + for<'de> Deserialize<'de> + 'static {
    const WIDTH: usize;
    const ZERO: Self;
    fn from_le(bytes: &[u8]) -> Self;
    fn write_le(self, out: &mut Vec<u8>);
}

macro_rules! element {
    ($($t:ty),*) => {$(
        impl Element for $t {
            const WIDTH: usize = std::mem::size_of::<$t>();
            const ZERO: Self = 0 as $t;
            #[inline]
            fn from_le(bytes: &[u8]) -> Self {
                <$t>::from_le_bytes(bytes.try_into().expect("chunks of the element's width"))
            }
            #[inline]
            fn write_le(self, out: &mut Vec<u8>) {
                out.extend_from_slice(&self.to_le_bytes());
            }
        }
    )*};
}
element!(u32, u64, f32, f64);

/// Serializes `values` as one byte string of little-endian values (a sequence for
/// human-readable formats).
pub fn serialize<T: Element, S: Serializer>(values: &[T], serializer: S) -> Result<S::Ok, S::Error> {
    if serializer.is_human_readable() {
        return serializer.collect_seq(values);
    }
    serializer.serialize_bytes(&le_bytes(values))
}

/// The little-endian bytes of `values`: their own memory on little-endian machines.
#[cfg(target_endian = "little")]
#[allow(unsafe_code)]
fn le_bytes<T: Element>(values: &[T]) -> std::borrow::Cow<'_, [u8]> {
    // SAFETY: `Element` is implemented only for u32, u64, f32 and f64: plain numbers without
    // padding whose every byte is initialised, so their memory may be read as bytes; on a
    // little-endian machine those bytes are the little-endian encoding. The slice borrows
    // `values` and covers exactly its `len * WIDTH` bytes.
    let bytes =
        unsafe { std::slice::from_raw_parts(values.as_ptr().cast::<u8>(), std::mem::size_of_val(values)) };
    std::borrow::Cow::Borrowed(bytes)
}

/// The memory of `values` as bytes to fill with their little-endian encoding (on
/// little-endian machines, where that is their memory): bulk arrays are read straight into it.
#[cfg(target_endian = "little")]
#[allow(unsafe_code)]
pub(crate) fn le_bytes_mut<T: Element>(values: &mut [T]) -> &mut [u8] {
    // SAFETY: as in `le_bytes`; moreover every bit pattern is a valid u32, u64, f32 or f64, so
    // any bytes written through the slice leave valid values. The slice borrows `values`
    // mutably and covers exactly its `len * WIDTH` bytes.
    unsafe { std::slice::from_raw_parts_mut(values.as_mut_ptr().cast::<u8>(), std::mem::size_of_val(values)) }
}

#[cfg(not(target_endian = "little"))]
#[allow(unsafe_code)]
fn le_bytes<T: Element>(values: &[T]) -> std::borrow::Cow<'_, [u8]> {
    let mut out = Vec::with_capacity(values.len() * T::WIDTH);
    for &v in values {
        v.write_le(&mut out);
    }
    std::borrow::Cow::Owned(out)
}

/// Reads what [`serialize`] wrote.
pub fn deserialize<'de, T: Element, D: Deserializer<'de>>(deserializer: D) -> Result<Vec<T>, D::Error> {
    if deserializer.is_human_readable() {
        return Vec::<T>::deserialize(deserializer);
    }
    deserializer.deserialize_bytes(LeVisitor(PhantomData))
}

/// Decodes a byte string of little-endian `T`s.
fn from_le_bytes<T: Element, E: serde::de::Error>(bytes: &[u8]) -> Result<Vec<T>, E> {
    if !bytes.len().is_multiple_of(T::WIDTH) {
        return Err(E::custom(format!(
            "a bulk array of {}-byte numbers has {} bytes",
            T::WIDTH,
            bytes.len()
        )));
    }
    Ok(bytes.chunks_exact(T::WIDTH).map(T::from_le).collect())
}

struct LeVisitor<T>(PhantomData<T>);

impl<'de, T: Element> Visitor<'de> for LeVisitor<T> {
    type Value = Vec<T>;

    fn expecting(&self, f: &mut std::fmt::Formatter) -> std::fmt::Result {
        write!(f, "a byte string of little-endian {}-byte numbers", T::WIDTH)
    }

    fn visit_bytes<E: serde::de::Error>(self, bytes: &[u8]) -> Result<Vec<T>, E> {
        from_le_bytes(bytes)
    }

    fn visit_byte_buf<E: serde::de::Error>(self, bytes: Vec<u8>) -> Result<Vec<T>, E> {
        from_le_bytes(&bytes)
    }

    fn visit_seq<A: SeqAccess<'de>>(self, mut seq: A) -> Result<Vec<T>, A::Error> {
        // The hint comes from the input: trusted only up to a megabyte.
        let mut bytes = Vec::with_capacity(seq.size_hint().unwrap_or(0).min(1 << 20));
        while let Some(b) = seq.next_element::<u8>()? {
            bytes.push(b);
        }
        from_le_bytes::<T, A::Error>(&bytes)
    }
}

#[cfg(test)]
mod tests {
    use serde::{Deserialize, Serialize};

    #[derive(Debug, PartialEq, Serialize, Deserialize)]
    struct Arrays {
        #[serde(with = "super")]
        targets: Vec<u32>,
        #[serde(with = "super")]
        costs: Vec<f32>,
        #[serde(with = "super")]
        positions: Vec<f64>,
        name: String,
    }

    fn sample() -> Arrays {
        Arrays {
            targets: vec![0, 1, u32::MAX, 70_000],
            costs: vec![0.5, f32::MIN_POSITIVE, 1e30],
            positions: vec![-1.25, 1e-300],
            name: "n".into(),
        }
    }

    #[test]
    fn postcard_round_trip_is_raw_little_endian_bytes() {
        let bytes = postcard::to_stdvec(&sample()).unwrap();
        // One length byte then 16 bytes of targets, the first being 0u32 and the third u32::MAX.
        assert_eq!(bytes[0], 16);
        assert_eq!(&bytes[1..5], &[0, 0, 0, 0]);
        assert_eq!(&bytes[9..13], &[0xff; 4]);
        assert_eq!(&bytes[13..17], &70_000u32.to_le_bytes());
        assert_eq!(bytes.len(), 1 + 16 + 1 + 12 + 1 + 16 + 2);
        assert_eq!(postcard::from_bytes::<Arrays>(&bytes).unwrap(), sample());
    }

    #[test]
    fn json_sees_plain_numbers() {
        let text = serde_json::to_string(&sample()).unwrap();
        assert!(text.starts_with("{\"targets\":[0,1,4294967295,70000],"), "{text}");
        assert_eq!(serde_json::from_str::<Arrays>(&text).unwrap(), sample());
    }

    #[test]
    fn a_truncated_array_is_an_error() {
        let mut bytes = postcard::to_stdvec(&sample()).unwrap();
        bytes[0] = 15; // 15 bytes of u32: not a whole number of values
        let err = postcard::from_bytes::<Arrays>(&bytes).unwrap_err();
        assert!(!err.to_string().is_empty());
    }
}
