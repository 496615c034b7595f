//! The scene's top-level sections, and a record of which ones a stage read.
//!
//! A stage's artifact key hashes exactly the sections its row of the stage table declares, so
//! editing any other section leaves the artifact up to date. That is only right if the stage
//! reads no other section: [`Scene`](crate::Scene) hands its sections out through accessors
//! that note each read in a [`Reads`] record when auditing is on, and the pipeline's tests
//! compare what every stage read with what it declares, in both directions.

use std::sync::atomic::{AtomicU32, Ordering};

/// A top-level section of the scene file (or one field of one: `skeleton.forced_links`,
/// `hydro.total_discharge`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord)]
pub enum Section {
    Seed,
    Domain,
    Terrain,
    Geology,
    Keypoints,
    Connectivity,
    Phases,
    Sampling,
    Costgraph,
    Skeleton,
    ForcedLinks,
    Hydro,
    TotalDischarge,
    Streams,
    Sdf,
    Mesher,
    Export,
    Calibrate,
}

impl Section {
    /// Every section.
    pub const ALL: [Section; 18] = [
        Section::Seed,
        Section::Domain,
        Section::Terrain,
        Section::Geology,
        Section::Keypoints,
        Section::Connectivity,
        Section::Phases,
        Section::Sampling,
        Section::Costgraph,
        Section::Skeleton,
        Section::ForcedLinks,
        Section::Hydro,
        Section::TotalDischarge,
        Section::Streams,
        Section::Sdf,
        Section::Mesher,
        Section::Export,
        Section::Calibrate,
    ];

    /// The section's name in the scene file, as the stage table writes it.
    pub fn key(self) -> &'static str {
        match self {
            Section::Seed => "seed",
            Section::Domain => "domain",
            Section::Terrain => "terrain",
            Section::Geology => "geology",
            Section::Keypoints => "keypoints",
            Section::Connectivity => "connectivity",
            Section::Phases => "phases",
            Section::Sampling => "sampling",
            Section::Costgraph => "costgraph",
            Section::Skeleton => "skeleton",
            Section::ForcedLinks => "skeleton.forced_links",
            Section::Hydro => "hydro",
            Section::TotalDischarge => "hydro.total_discharge",
            Section::Streams => "streams",
            Section::Sdf => "sdf",
            Section::Mesher => "mesher",
            Section::Export => "export",
            Section::Calibrate => "calibrate",
        }
    }

    /// The section named `key`.
    pub fn from_key(key: &str) -> Option<Section> {
        Section::ALL.into_iter().find(|s| s.key() == key)
    }
}

/// Which sections were read since auditing started; off (and free but for one branch) unless
/// asked for.
#[derive(Debug, Default)]
pub(crate) struct Reads {
    auditing: bool,
    bits: AtomicU32,
}

impl Reads {
    /// A record that notes every read.
    pub(crate) fn auditing() -> Self {
        Reads { auditing: true, bits: AtomicU32::new(0) }
    }

    /// Notes a read of `section`.
    #[inline]
    pub(crate) fn note(&self, section: Section) {
        if self.auditing {
            self.bits.fetch_or(1 << section as u32, Ordering::Relaxed);
        }
    }

    /// The sections read so far, in table order.
    pub(crate) fn read(&self) -> Vec<Section> {
        let bits = self.bits.load(Ordering::Relaxed);
        Section::ALL.into_iter().filter(|s| bits & (1 << *s as u32) != 0).collect()
    }
}

impl Clone for Reads {
    /// A clone audits if the original did, from a clean record.
    fn clone(&self) -> Self {
        Reads { auditing: self.auditing, bits: AtomicU32::new(0) }
    }
}

impl PartialEq for Reads {
    /// The record is not part of a scene's value.
    fn eq(&self, _: &Self) -> bool {
        true
    }
}
