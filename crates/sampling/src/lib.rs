//! Stage 1: sampling the bedrock.
//!
//! Conduits can only run through samples, so the sampler decides what the network can follow.
//! Key points go in first, exactly, and are never dropped (even when two are closer than the
//! radius); then samples on the water tables, horizons and faults themselves; then the volume
//! below the terrain and outside the no-karst volumes, all spaced by a variable radius field
//! ([`SpacingField`], `spacing.rs`) with a fast, deterministic dart-throwing sampler
//! (`poisson.rs`). [`build`] is the algorithm's entry, [`SamplingStage`] the stage; the output is
//! `samples.bin` ([`Samples`], `payload.rs`).

mod build;
mod error;
mod estimate;
mod order;
mod payload;
mod poisson;
mod spacing;
mod stage;
mod surfaces;
mod view;

pub use build::build;
pub use error::SamplingError;
pub use order::morton_permutation;
pub use payload::{Samples, Tag, TagCounts};
pub use spacing::SpacingField;
pub use stage::SamplingStage;
pub use view::SamplingView;
