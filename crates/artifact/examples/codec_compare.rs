//! Measures the bulk-artifact codecs on a costgraph-sized payload (100k samples, k = 50):
//! `cargo run --release -p karst-artifact --example codec_compare`. The README records the
//! result that chose postcard.

use std::time::Instant;

use serde::{Deserialize, Serialize};

#[derive(Serialize, Deserialize, PartialEq)]
struct Csr {
    offsets: Vec<u32>,
    targets: Vec<u32>,
    costs: Vec<f32>,
}

fn payload() -> Csr {
    let (n, k) = (100_000u32, 50u32);
    let mut state = 1u64;
    let mut next = || {
        state = state.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
        (state >> 33) as u32
    };
    Csr {
        offsets: (0..=n).map(|i| i * k).collect(),
        targets: (0..n * k).map(|_| next() % n).collect(),
        costs: (0..n * k).map(|_| next() as f32 / 1e6).collect(),
    }
}

fn median(mut v: Vec<f64>) -> f64 {
    v.sort_by(f64::total_cmp);
    v[v.len() / 2]
}

fn measure(name: &str, data: &Csr, encode: impl Fn(&Csr) -> Vec<u8>, decode: impl Fn(&[u8]) -> Csr) {
    let (mut enc, mut dec) = (Vec::new(), Vec::new());
    let mut bytes = Vec::new();
    for _ in 0..5 {
        let t = Instant::now();
        bytes = encode(data);
        enc.push(t.elapsed().as_secs_f64());
        let t = Instant::now();
        let back = decode(&bytes);
        dec.push(t.elapsed().as_secs_f64());
        assert!(back == *data);
    }
    println!(
        "{name:<22} {:>6.1} MB  encode {:>6.3} s  decode {:>6.3} s",
        bytes.len() as f64 / 1e6,
        median(enc),
        median(dec)
    );
}

fn main() {
    let data = payload();
    println!("costgraph payload: 100k samples, 5M directed edges (median of 5)");
    measure("postcard 1", &data, |d| postcard::to_stdvec(d).unwrap(), |b| postcard::from_bytes(b).unwrap());
    let standard = bincode::config::standard();
    measure(
        "bincode 2.0.1 standard",
        &data,
        |d| bincode::serde::encode_to_vec(d, standard).unwrap(),
        |b| bincode::serde::decode_from_slice(b, standard).unwrap().0,
    );
    let legacy = bincode::config::legacy();
    measure(
        "bincode 2.0.1 legacy",
        &data,
        |d| bincode::serde::encode_to_vec(d, legacy).unwrap(),
        |b| bincode::serde::decode_from_slice(b, legacy).unwrap().0,
    );
}
