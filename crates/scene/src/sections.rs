//! The scene's top-level sections (and the fields of sections read on their own): what a
//! stage's view holds ([`crate::view`]) and its artifact key hashes.

/// A top-level section of the scene file (or one field of one: `skeleton.forced_links`,
/// `hydro.total_discharge`, `sdf.passage_detail`; `calibrate.aim` is `calibrate.like` or
/// `calibrate.target`).
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
    PassageDetail,
    Mesher,
    Export,
    Calibrate,
    CalibrationAim,
}

impl Section {
    /// Every section.
    pub const ALL: [Section; 20] = [
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
        Section::PassageDetail,
        Section::Mesher,
        Section::Export,
        Section::Calibrate,
        Section::CalibrationAim,
    ];

    /// The section's name in the scene file (a dotted name is one field of a section).
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
            Section::PassageDetail => "sdf.passage_detail",
            Section::Mesher => "mesher",
            Section::Export => "export",
            Section::Calibrate => "calibrate",
            Section::CalibrationAim => "calibrate.aim",
        }
    }

    /// The section named `key`.
    pub fn from_key(key: &str) -> Option<Section> {
        Section::ALL.into_iter().find(|s| s.key() == key)
    }
}
