//! Stage 1: sampling the bedrock.
//!
//! Conduits can only run through samples, so the sampler decides what the network can follow.
//! This first version fills the bedrock (the domain below the terrain) with a Poisson-disk
//! distribution of constant radius (Bridson 2007, in 3D) after inserting every key point
//! exactly; key points are never dropped, even when two are closer than the radius.
//! Output: `samples.bin` ([`Samples`]).

pub mod poisson;
pub mod samples;
pub mod stage;

pub use samples::{Samples, Tag};
