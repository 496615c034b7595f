//! Fuzz targets that stay: property-based fuzzing on stable Rust (proptest), run a few
//! thousand cases per target by the test suite and for as long as asked by
//! `cargo xtask fuzz --minutes N`.
//!
//! Each [`Target`] feeds one of karstgen's readers with mutations of real inputs: the scene
//! parser and validator (scenes of `fixtures/scenes`), every artifact decoder and its
//! `Payload::validate` (the tiny goldens' payloads) followed by what `inspect` computes from a
//! payload that passes, what the export writers and the viewer make of payloads that pass, the
//! viewer's ensemble grid, the network readers (karstnet, GOCAD PLine, CSV) followed by the
//! metrics, and the data-file readers (TSurf, plain TIN, PNG heightfield). The property is the
//! same everywhere: whatever the bytes, the reader returns (a value or an error); it never
//! panics. Mutations ([`mutate`]) flip and overwrite bytes, splice in the numbers that break
//! code (NaN, ±∞, 1e308, the smallest subnormal, −1, 2³²), lengthen arrays and drop or repeat
//! lines; proptest shrinks a failing case to a small one, which [`save`] writes into
//! `fixtures/bad/fuzz/<target>/`, where the test suite replays every file for good.

pub mod mutate;
pub mod targets;

use std::path::{Path, PathBuf};
use std::time::Instant;

use proptest::test_runner::{Config, RngAlgorithm, TestError, TestRng, TestRunner};

pub use targets::{Target, targets};

/// A panic found: the target, the (shrunk) input and the panic's message.
#[derive(Debug, Clone)]
pub struct Failure {
    pub target: &'static str,
    pub input: Vec<u8>,
    pub message: String,
}

impl std::fmt::Display for Failure {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "{}: {} ({} bytes of input)", self.target, self.message, self.input.len())
    }
}

/// Runs `cases` mutated inputs through `target`, from the random stream `seed`.
pub fn run(target: &Target, cases: u32, seed: u64) -> Result<(), Failure> {
    let config = Config { cases, failure_persistence: None, max_shrink_iters: 2048, ..Config::default() };
    let mut key = [0u8; 32];
    key[..8].copy_from_slice(&seed.to_le_bytes());
    key[8..16].copy_from_slice(&blake3::hash(target.name.as_bytes()).as_bytes()[..8]);
    let mut runner = TestRunner::new_with_rng(config, TestRng::from_seed(RngAlgorithm::ChaCha, &key));
    let strategy = mutate::inputs((target.seeds)(), target.text);
    let check = target.check;
    match runner.run(&strategy, |input| {
        check(&input);
        Ok(())
    }) {
        Ok(()) => Ok(()),
        Err(TestError::Fail(reason, input)) => {
            Err(Failure { target: target.name, input, message: reason.message().to_string() })
        }
        Err(TestError::Abort(reason)) => {
            Err(Failure { target: target.name, input: Vec::new(), message: format!("aborted: {reason}") })
        }
    }
}

/// Runs every target in turn, `batch` cases at a time with a new seed each round, until
/// `seconds` have passed; returns the failures found (at most one per target and round).
pub fn run_for(seconds: f64, batch: u32, first_seed: u64) -> Vec<Failure> {
    let start = Instant::now();
    let targets = targets();
    let mut failures = Vec::new();
    let mut seed = first_seed;
    while start.elapsed().as_secs_f64() < seconds {
        for target in &targets {
            if let Err(failure) = run(target, batch, seed) {
                failures.push(failure);
            }
            if start.elapsed().as_secs_f64() >= seconds {
                break;
            }
        }
        seed += 1;
    }
    failures
}

/// Where the failures of `target` are kept: `fixtures/bad/fuzz/<target>/`.
pub fn regression_dir(root: &Path, target: &str) -> PathBuf {
    root.join("fixtures/bad/fuzz").join(target)
}

/// Writes the input of `failure` as a regression case (named by its BLAKE3) and returns the
/// file.
pub fn save(root: &Path, failure: &Failure) -> std::io::Result<PathBuf> {
    let dir = regression_dir(root, failure.target);
    std::fs::create_dir_all(&dir)?;
    let name = blake3::hash(&failure.input).to_hex()[..16].to_string();
    let file = dir.join(name);
    karst_artifact::atomic::write_bytes(&file, &failure.input)?;
    Ok(file)
}

/// Replays every regression case of `target` kept under `root`; returns how many.
pub fn replay(root: &Path, target: &Target) -> std::io::Result<usize> {
    let dir = regression_dir(root, target.name);
    let Ok(entries) = std::fs::read_dir(&dir) else { return Ok(0) };
    let mut files: Vec<PathBuf> = entries.flatten().map(|e| e.path()).filter(|p| p.is_file()).collect();
    files.sort();
    for file in &files {
        (target.check)(&std::fs::read(file)?);
    }
    Ok(files.len())
}
