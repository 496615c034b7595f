//! The stage table: which stages exist, in which order, and for each one row saying what it
//! is called, which binary runs it, which artifact file it writes and how that file is
//! encoded, and which upstream artifacts it reads. `karstgen run`, every stage binary and the
//! artifact reader all use this one table, so that they always agree on staleness and on what
//! to rerun. (The scene sections a stage reads are its view's, declared in its crate.)

use serde::{Deserialize, Serialize};

use crate::hash;

/// A stage of the pipeline, in run order. Serialized as its artifact's kind name
/// (`"samples"`, `"mesh"`): that is the `kind` field of every artifact header.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord, Serialize, Deserialize)]
pub enum StageId {
    #[serde(rename = "samples")]
    Sampling,
    #[serde(rename = "costgraph")]
    Costgraph,
    #[serde(rename = "skeleton")]
    Skeleton,
    #[serde(rename = "hydro")]
    Hydro,
    #[serde(rename = "streams")]
    Streams,
    #[serde(rename = "sdf")]
    Sdf,
    #[serde(rename = "mesh")]
    Mesher,
    #[serde(rename = "survey")]
    Survey,
    #[serde(rename = "metrics")]
    Metrics,
    #[serde(rename = "export")]
    Export,
}

/// How an artifact's payload is encoded.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
pub enum Encoding {
    /// postcard 1.x wire format, after a one-line JSON header.
    #[serde(rename = "postcard-1")]
    Postcard,
    /// Pretty-printed JSON, as the `payload` field of one JSON document.
    #[serde(rename = "json")]
    Json,
}

/// One row of the stage table.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct StageRow {
    /// The stage's name on the command line (`--from costgraph`).
    pub name: &'static str,
    /// The artifact kind it writes, as in the header (`"samples"`).
    pub kind: &'static str,
    /// The stage's own binary.
    pub binary: &'static str,
    /// The artifact's file name inside the output folder.
    pub file: &'static str,
    /// How the artifact's payload is encoded.
    pub encoding: Encoding,
    /// The upstream stages whose artifacts it reads.
    pub inputs: &'static [StageId],
}

use Encoding::{Json, Postcard};
use StageId::*;

/// The table, in run order; `TABLE[id as usize]` is `id`'s row.
const TABLE: [StageRow; 10] = [
    StageRow {
        name: "sampling",
        kind: "samples",
        binary: "karst-sampling",
        file: "samples.bin",
        encoding: Postcard,
        inputs: &[],
    },
    StageRow {
        name: "costgraph",
        kind: "costgraph",
        binary: "karst-costgraph",
        file: "costgraph.bin",
        encoding: Postcard,
        inputs: &[Sampling],
    },
    StageRow {
        name: "skeleton",
        kind: "skeleton",
        binary: "karst-skeleton",
        file: "skeleton.json",
        encoding: Json,
        inputs: &[Sampling, Costgraph],
    },
    StageRow {
        name: "hydro",
        kind: "hydro",
        binary: "karst-hydro",
        file: "hydro.json",
        encoding: Json,
        inputs: &[Skeleton],
    },
    StageRow {
        name: "streams",
        kind: "streams",
        binary: "karst-streams",
        file: "streams.json",
        encoding: Json,
        inputs: &[Hydro],
    },
    StageRow {
        name: "sdf",
        kind: "sdf",
        binary: "karst-sdf",
        file: "sdf.bin",
        encoding: Postcard,
        inputs: &[Skeleton, Hydro, Streams],
    },
    StageRow {
        name: "mesher",
        kind: "mesh",
        binary: "karst-mesher",
        file: "mesh.bin",
        encoding: Postcard,
        inputs: &[Sdf],
    },
    StageRow {
        name: "survey",
        kind: "survey",
        binary: "karst-survey",
        file: "survey.json",
        encoding: Json,
        inputs: &[Skeleton, Sdf],
    },
    StageRow {
        name: "metrics",
        kind: "metrics",
        binary: "karst-metrics",
        file: "metrics.json",
        encoding: Json,
        inputs: &[Skeleton, Hydro, Streams, Survey],
    },
    StageRow {
        name: "export",
        kind: "export",
        binary: "karst-export",
        file: "export.json",
        encoding: Json,
        inputs: &[Sampling, Skeleton, Hydro, Streams, Mesher, Metrics],
    },
];

impl StageId {
    /// Every stage, in run order.
    pub const ALL: [StageId; 10] =
        [Sampling, Costgraph, Skeleton, Hydro, Streams, Sdf, Mesher, Survey, Metrics, Export];

    /// The stage's row of the table.
    pub fn row(self) -> &'static StageRow {
        &TABLE[self as usize]
    }

    /// The stage's name, as used on the command line.
    pub fn name(self) -> &'static str {
        self.row().name
    }

    /// The artifact's file name inside the output folder.
    pub fn file_name(self) -> &'static str {
        self.row().file
    }

    /// The upstream stages whose artifacts this stage reads.
    pub fn inputs(self) -> &'static [StageId] {
        self.row().inputs
    }

    /// Parses a stage name (`sampling`) or an artifact kind name (`samples`).
    pub fn from_name(name: &str) -> Option<StageId> {
        StageId::ALL.into_iter().find(|s| s.row().name == name || s.row().kind == name)
    }
}

/// The key of an artifact: the hash of the stage, the producer's name and version, the payload
/// schema, the hash of the scene sections it reads and its inputs' payload hashes. Equal keys
/// mean the stage would write the same artifact again.
pub fn stage_key(
    stage: StageId,
    producer: &str,
    schema: u32,
    params: &str,
    frame: &crate::Frame,
    inputs: &[crate::InputRef],
) -> String {
    let schema = schema.to_le_bytes();
    let frame = frame.key_text();
    let mut parts: Vec<&[u8]> = vec![
        b"karstgen-key-1",
        stage.name().as_bytes(),
        producer.as_bytes(),
        &schema,
        params.as_bytes(),
        frame.as_bytes(),
    ];
    for input in inputs {
        parts.push(input.name.as_bytes());
        parts.push(input.payload_blake3.as_bytes());
    }
    hash::hex_of_parts(parts)
}

/// The producer string written by this build for `stage`.
pub fn producer(stage: StageId) -> String {
    format!("{} {}", stage.row().binary, env!("CARGO_PKG_VERSION"))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::InputRef;

    #[test]
    fn the_table_is_in_run_order_and_names_are_unique() {
        for (i, stage) in StageId::ALL.into_iter().enumerate() {
            assert_eq!(stage as usize, i);
            for input in stage.inputs() {
                assert!(input < &stage, "{} reads {}", stage.name(), input.name());
            }
            assert_eq!(StageId::from_name(stage.name()), Some(stage));
            assert_eq!(StageId::from_name(stage.row().kind), Some(stage));
            let json = serde_json::to_string(&stage).unwrap();
            assert_eq!(json, format!("\"{}\"", stage.row().kind));
        }
        let mut files: Vec<&str> = StageId::ALL.iter().map(|s| s.file_name()).collect();
        files.sort();
        files.dedup();
        assert_eq!(files.len(), StageId::ALL.len());
    }

    #[test]
    fn key_depends_on_everything() {
        let input = |h: &str| InputRef { name: "samples".into(), payload_blake3: h.into() };
        let local = crate::Frame::default();
        let moved = crate::Frame { origin: [650000.0, 5100000.0, 0.0], crs: None };
        let base = stage_key(Costgraph, "p 1", 1, "params", &local, &[input("a")]);
        assert_ne!(base, stage_key(Costgraph, "p 2", 1, "params", &local, &[input("a")]));
        assert_ne!(base, stage_key(Costgraph, "p 1", 2, "params", &local, &[input("a")]));
        assert_ne!(base, stage_key(Costgraph, "p 1", 1, "other", &local, &[input("a")]));
        assert_ne!(base, stage_key(Costgraph, "p 1", 1, "params", &moved, &[input("a")]));
        assert_ne!(base, stage_key(Costgraph, "p 1", 1, "params", &local, &[input("b")]));
        assert_ne!(base, stage_key(Skeleton, "p 1", 1, "params", &local, &[input("a")]));
        assert_eq!(base, stage_key(Costgraph, "p 1", 1, "params", &local, &[input("a")]));
    }
}
