//! The stage table: which stages exist, in which order, what each reads and writes, and the key
//! that decides whether an artifact is up to date. `cargo xtask run` and every stage binary use
//! this one table, so that they always agree on staleness.

use crate::envelope::{InputRef, Kind};
use crate::hash;

/// The pipeline's stages, in run order.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum Stage {
    Sampling,
    Costgraph,
    Skeleton,
    Hydro,
    Sdf,
    Mesher,
    Metrics,
}

impl Stage {
    /// Every stage, in run order.
    pub const ALL: [Stage; 7] = [
        Stage::Sampling,
        Stage::Costgraph,
        Stage::Skeleton,
        Stage::Hydro,
        Stage::Sdf,
        Stage::Mesher,
        Stage::Metrics,
    ];

    /// The stage's name, as used on the command line (`--from costgraph`).
    pub fn name(self) -> &'static str {
        match self {
            Stage::Sampling => "sampling",
            Stage::Costgraph => "costgraph",
            Stage::Skeleton => "skeleton",
            Stage::Hydro => "hydro",
            Stage::Sdf => "sdf",
            Stage::Mesher => "mesher",
            Stage::Metrics => "metrics",
        }
    }

    /// Parses a stage name.
    pub fn from_name(name: &str) -> Option<Stage> {
        Stage::ALL.into_iter().find(|s| s.name() == name)
    }

    /// The kind of artifact the stage writes.
    pub fn kind(self) -> Kind {
        match self {
            Stage::Sampling => Kind::Samples,
            Stage::Costgraph => Kind::Costgraph,
            Stage::Skeleton => Kind::Skeleton,
            Stage::Hydro => Kind::Hydro,
            Stage::Sdf => Kind::Sdf,
            Stage::Mesher => Kind::Mesh,
            Stage::Metrics => Kind::Metrics,
        }
    }

    /// The stage that writes artifacts of `kind`.
    pub fn of_kind(kind: Kind) -> Stage {
        Stage::ALL.into_iter().find(|s| s.kind() == kind).expect("every kind has a stage")
    }

    /// The artifact's file name inside the output folder.
    pub fn file_name(self) -> &'static str {
        match self {
            Stage::Sampling => "samples.bin",
            Stage::Costgraph => "costgraph.bin",
            Stage::Skeleton => "skeleton.json",
            Stage::Hydro => "hydro.json",
            Stage::Sdf => "sdf.bin",
            Stage::Mesher => "mesh.bin",
            Stage::Metrics => "metrics.json",
        }
    }

    /// The stage's binary.
    pub fn binary(self) -> &'static str {
        match self {
            Stage::Sampling => "karst-sampling",
            Stage::Costgraph => "karst-costgraph",
            Stage::Skeleton => "karst-skeleton",
            Stage::Hydro => "karst-hydro",
            Stage::Sdf => "karst-sdf",
            Stage::Mesher => "karst-mesher",
            Stage::Metrics => "karst-metrics",
        }
    }

    /// The upstream stages whose artifacts this stage reads.
    pub fn inputs(self) -> &'static [Stage] {
        match self {
            Stage::Sampling => &[],
            Stage::Costgraph => &[Stage::Sampling],
            Stage::Skeleton => &[Stage::Sampling, Stage::Costgraph],
            Stage::Hydro => &[Stage::Skeleton],
            Stage::Sdf => &[Stage::Skeleton, Stage::Hydro],
            Stage::Mesher => &[Stage::Sdf],
            Stage::Metrics => &[Stage::Skeleton, Stage::Hydro],
        }
    }

    /// The scene sections this stage reads; their hash is part of the artifact key, so editing
    /// any other section leaves the artifact up to date.
    pub fn scene_sections(self) -> &'static [&'static str] {
        match self {
            Stage::Sampling => &["seed", "domain", "terrain", "geology", "keypoints", "sampling"],
            Stage::Costgraph => &[
                "domain",
                "terrain",
                "geology",
                "keypoints",
                "connectivity",
                "costgraph",
                "skeleton.forced_links",
            ],
            Stage::Skeleton => {
                &["seed", "domain", "terrain", "geology", "keypoints", "connectivity", "phases", "skeleton"]
            }
            Stage::Hydro => &["domain", "terrain", "keypoints", "hydro"],
            Stage::Sdf => &["seed", "domain", "terrain", "sdf"],
            Stage::Mesher => &["domain", "mesher"],
            Stage::Metrics => &["metrics"],
        }
    }
}

/// The key of an artifact: the hash of the stage, the producer's name and version, the payload
/// schema, the hash of the scene sections it reads and its inputs' payload hashes. Equal keys
/// mean the stage would write the same artifact again.
pub fn stage_key(stage: Stage, producer: &str, schema: u32, params: &str, inputs: &[InputRef]) -> String {
    let schema = schema.to_le_bytes();
    let mut parts: Vec<&[u8]> =
        vec![b"karstgen-key-1", stage.name().as_bytes(), producer.as_bytes(), &schema, params.as_bytes()];
    for input in inputs {
        parts.push(input.name.as_bytes());
        parts.push(input.payload_blake3.as_bytes());
    }
    hash::hex_of_parts(parts)
}

/// The producer string written by the stage binaries of this build.
pub fn producer(stage: Stage) -> String {
    format!("{} {}", stage.binary(), env!("CARGO_PKG_VERSION"))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn inputs_come_before_their_stage() {
        for stage in Stage::ALL {
            for input in stage.inputs() {
                assert!(input < &stage, "{} reads {}", stage.name(), input.name());
            }
            assert_eq!(Stage::from_name(stage.name()), Some(stage));
            assert_eq!(Stage::of_kind(stage.kind()), stage);
        }
    }

    #[test]
    fn key_depends_on_everything() {
        let input = |h: &str| InputRef { name: "samples".into(), payload_blake3: h.into() };
        let base = stage_key(Stage::Costgraph, "p 1", 1, "params", &[input("a")]);
        assert_ne!(base, stage_key(Stage::Costgraph, "p 2", 1, "params", &[input("a")]));
        assert_ne!(base, stage_key(Stage::Costgraph, "p 1", 2, "params", &[input("a")]));
        assert_ne!(base, stage_key(Stage::Costgraph, "p 1", 1, "other", &[input("a")]));
        assert_ne!(base, stage_key(Stage::Costgraph, "p 1", 1, "params", &[input("b")]));
        assert_ne!(base, stage_key(Stage::Skeleton, "p 1", 1, "params", &[input("a")]));
        assert_eq!(base, stage_key(Stage::Costgraph, "p 1", 1, "params", &[input("a")]));
    }
}
