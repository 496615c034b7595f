//! Stage 1: sampling the bedrock.
//!
//! Conduits can only run through samples, so the sampler decides what the network can follow.
//! Key points go in first, exactly, and are never dropped (even when two are closer than the
//! radius); then samples on the water tables, horizons and faults themselves; then the volume
//! below the terrain and outside the no-karst volumes, all spaced by a variable radius field
//! (`radius.rs`) with a fast, deterministic dart-throwing sampler (`poisson.rs`).
//! Output: `samples.bin` ([`Samples`]).

pub mod poisson;
pub mod radius;
pub mod samples;
pub mod stage;
pub mod surfaces;

pub use radius::RadiusField;
pub use samples::{Samples, Tag, TagCounts};
