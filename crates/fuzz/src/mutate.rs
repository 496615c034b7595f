//! Mutations of a seed input, as a proptest strategy: bytes flipped, overwritten, inserted,
//! deleted or cut, and the numbers that break code spliced in, as bytes in binary inputs and
//! as number tokens in text; text also has lines dropped, repeated, swapped and arrays
//! lengthened. A case is a seed and a short list of mutations, so proptest shrinks a failure
//! to the seed and the few mutations that matter.

use std::sync::Arc;

use proptest::prelude::*;

/// One change to an input; positions are taken modulo the input's length.
#[derive(Debug, Clone)]
pub enum Mutation {
    Flip {
        at: u32,
        bit: u8,
    },
    Byte {
        at: u32,
        value: u8,
    },
    Insert {
        at: u32,
        bytes: Vec<u8>,
    },
    Delete {
        at: u32,
        len: u16,
    },
    Truncate {
        at: u32,
    },
    /// An interesting number written over the input (binary) or over its `at`-th number token
    /// (text).
    Number {
        at: u32,
        which: u8,
    },
    /// Text: drop (0), repeat (1) or swap with the next (2) the `at`-th line, or lengthen the
    /// first array on it (3).
    Line {
        at: u32,
        op: u8,
    },
}

/// Numbers that break code, as text.
const TEXT_NUMBERS: [&str; 18] = [
    "nan",
    "inf",
    "-inf",
    "1e308",
    "-1e308",
    "5e-324",
    "-1",
    "0",
    "-0",
    "4294967296",
    "4e9",
    "18446744073709551615",
    "9223372036854775807",
    "1e-300",
    "0.5",
    "\"x\"",
    "[]",
    "1e20",
];

/// Numbers that break code, as little-endian bytes (f64, u32, u64 and postcard varints of
/// huge lengths).
fn binary_number(which: u8) -> Vec<u8> {
    let f = [f64::NAN, f64::INFINITY, f64::NEG_INFINITY, 1e308, 5e-324, -1.0, 0.0, -0.0, 1e20];
    let i = which as usize % (f.len() + 6);
    match i.checked_sub(f.len()) {
        None => f[i].to_le_bytes().to_vec(),
        Some(0) => u32::MAX.to_le_bytes().to_vec(),
        Some(1) => 0x8000_0000u32.to_le_bytes().to_vec(),
        Some(2) => (f32::NAN).to_le_bytes().to_vec(),
        Some(3) => (-1.0f32).to_le_bytes().to_vec(),
        Some(4) => vec![0xff, 0xff, 0xff, 0xff, 0x0f],
        _ => vec![0xff, 0xff, 0xff, 0xff, 0xff, 0xff, 0xff, 0xff, 0xff, 0x01],
    }
}

fn mutation() -> impl Strategy<Value = Mutation> {
    prop_oneof![
        (any::<u32>(), 0u8..8).prop_map(|(at, bit)| Mutation::Flip { at, bit }),
        (any::<u32>(), any::<u8>()).prop_map(|(at, value)| Mutation::Byte { at, value }),
        (any::<u32>(), prop::collection::vec(any::<u8>(), 1..8))
            .prop_map(|(at, bytes)| Mutation::Insert { at, bytes }),
        (any::<u32>(), 1u16..64).prop_map(|(at, len)| Mutation::Delete { at, len }),
        any::<u32>().prop_map(|at| Mutation::Truncate { at }),
        (any::<u32>(), any::<u8>()).prop_map(|(at, which)| Mutation::Number { at, which }),
        (any::<u32>(), any::<u8>()).prop_map(|(at, which)| Mutation::Number { at, which }),
        (any::<u32>(), 0u8..4).prop_map(|(at, op)| Mutation::Line { at, op }),
    ]
}

/// Inputs made from `seeds` by up to five mutations each (text mutations when `text`).
pub fn inputs(seeds: Vec<Vec<u8>>, text: bool) -> BoxedStrategy<Vec<u8>> {
    let count = seeds.len();
    let seeds = Arc::new(seeds);
    (0..count, prop::collection::vec(mutation(), 0..6))
        .prop_map(move |(seed, mutations)| {
            let mut input = seeds[seed].clone();
            for m in &mutations {
                apply(&mut input, m, text);
            }
            input
        })
        .boxed()
}

/// Applies one mutation.
pub fn apply(input: &mut Vec<u8>, mutation: &Mutation, text: bool) {
    let len = input.len();
    let at = |p: u32| if len == 0 { 0 } else { p as usize % len };
    match mutation {
        Mutation::Flip { at: p, bit } if len > 0 => input[at(*p)] ^= 1 << bit,
        Mutation::Byte { at: p, value } if len > 0 => input[at(*p)] = *value,
        Mutation::Insert { at: p, bytes } => {
            let i = at(*p);
            input.splice(i..i, bytes.iter().copied());
        }
        Mutation::Delete { at: p, len: n } if len > 0 => {
            let i = at(*p);
            input.drain(i..(i + *n as usize).min(len));
        }
        Mutation::Truncate { at: p } => input.truncate(at(*p)),
        Mutation::Number { at: p, which } if text => replace_number(input, *p, *which),
        Mutation::Number { at: p, which } if len > 0 => {
            let bytes = binary_number(*which);
            let i = at(*p);
            let end = (i + bytes.len()).min(len);
            input[i..end].copy_from_slice(&bytes[..end - i]);
        }
        Mutation::Line { at: p, op } if text => edit_line(input, *p, *op),
        _ => {}
    }
}

/// Replaces the `k`-th number token (modulo their count) by an interesting one.
fn replace_number(input: &mut Vec<u8>, k: u32, which: u8) {
    let mut tokens = Vec::new();
    let mut i = 0;
    while i < input.len() {
        let starts = input[i].is_ascii_digit()
            || (input[i] == b'-' && input.get(i + 1).is_some_and(|c| c.is_ascii_digit()));
        let inside_word = i > 0 && (input[i - 1].is_ascii_alphanumeric() || input[i - 1] == b'_');
        if starts && !inside_word {
            let start = i;
            i += 1;
            while i < input.len() && (input[i].is_ascii_digit() || b".eE+-_".contains(&input[i])) {
                i += 1;
            }
            tokens.push(start..i);
        } else {
            i += 1;
        }
    }
    if tokens.is_empty() {
        return;
    }
    let range = tokens[k as usize % tokens.len()].clone();
    let number = TEXT_NUMBERS[which as usize % TEXT_NUMBERS.len()];
    input.splice(range, number.bytes());
}

/// Drops, repeats or swaps the `k`-th line, or lengthens the first array on it.
fn edit_line(input: &mut Vec<u8>, k: u32, op: u8) {
    let text = String::from_utf8_lossy(input).into_owned();
    let mut lines: Vec<String> = text.lines().map(str::to_string).collect();
    if lines.is_empty() {
        return;
    }
    let i = k as usize % lines.len();
    match op {
        0 => {
            lines.remove(i);
        }
        1 => lines.insert(i, lines[i].clone()),
        2 if i + 1 < lines.len() => lines.swap(i, i + 1),
        _ => {
            if let Some(end) = lines[i].find(']') {
                lines[i].insert_str(end, ", 7");
            }
        }
    }
    *input = (lines.join("\n") + "\n").into_bytes();
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn text_mutations_touch_numbers_lines_and_arrays() {
        let mut scene = b"max = [1, 2, 3]\nradius = 8.0\n".to_vec();
        apply(&mut scene, &Mutation::Number { at: 3, which: 0 }, true);
        assert_eq!(String::from_utf8_lossy(&scene), "max = [1, 2, 3]\nradius = nan\n");
        apply(&mut scene, &Mutation::Line { at: 0, op: 3 }, true);
        assert!(String::from_utf8_lossy(&scene).starts_with("max = [1, 2, 3, 7]\n"));
        apply(&mut scene, &Mutation::Line { at: 1, op: 0 }, true);
        assert_eq!(String::from_utf8_lossy(&scene), "max = [1, 2, 3, 7]\n");
        let mut bytes = vec![0u8; 12];
        apply(&mut bytes, &Mutation::Number { at: 2, which: 0 }, false);
        assert!(f64::from_le_bytes(bytes[2..10].try_into().unwrap()).is_nan());
    }
}
