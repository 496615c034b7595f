//! Karst network statistics, identical to karstnet 1.2.5.
//!
//! [`characterize`] computes every metric of `karstnet.KGraph.characterize_graph()` plus the
//! counts printed by `basic_analysis()`, Howard's parameters, the connectivity degree DC, the
//! Sturges entropy variants and karstnet's length-weighted average shortest path length. The
//! definitions are written out in `docs/metrics-definitions.md` (the "spec" cited by section in
//! the module docs); values match karstnet to ~1e-14 relative.
//!
//! Pipeline (one module per step):
//! [`Network`] (validated) → `graph` (simple undirected graph in karstnet's node order) →
//! `branches` (spec §1) → `reduced` (spec §2) → `geometry` / `topology` (spec §3), with the
//! all-pairs traversals of the reduced graph in `shortest_paths` (exact integer length sums by
//! `quantum` and `bitbfs` where the lengths allow).
//!
//! [`ranges`] compares the metrics with real caves, `plots.rs` draws them. [`build`] makes the
//! stage's report of a skeleton ([`MetricsReport`], `payload.rs`), [`MetricsStage`] is the stage.
//!
//! [`published`] holds the statistics of the published networks `calibrate --like` aims at.
//!
//! [`readers`] load karstnet `_nodes.dat`/`_links.dat` pairs, GOCAD PLines and CSV tables.

pub mod aim;
mod bitbfs;
mod branches;
mod build;
mod error;
mod geometry;
mod graph;
pub mod hints;
mod metrics;
mod network;
mod nullable;
mod payload;
mod plots;
pub mod published;
mod quantum;
pub mod ranges;
pub mod readers;
mod reduced;
mod shortest_paths;
pub mod stage;
mod topology;
mod view;

pub use build::{build, network_of, report, surface_water, water_type_lengths, zone_lengths};
pub use error::ReportError;
pub use metrics::{Distributions, Metrics, characterize, distributions};
pub use network::{MetricsError, Network};
pub use payload::{MetricsReport, SurfaceWater, ZoneLengths};
pub use readers::ReadError;
pub use stage::{MetricsStage, write_plots};
pub use view::MetricsView;
