//! The building blocks of the construction tree, each keeping the 1-Lipschitz bound: its
//! primitives — the terrain leaf ([`terrain`]), cross-sections ([`section`]) swept along
//! segments ([`sweep`]), capsules ([`capsule`]) and noise-biased chambers ([`chamber`]) — its
//! operators ([`ops`]) and the gradient-bounded noise that perturbs them ([`noise`]).

pub(crate) mod capsule;
pub(crate) mod chamber;
pub(crate) mod noise;
pub(crate) mod ops;
pub(crate) mod section;
pub(crate) mod sweep;
pub(crate) mod terrain;
