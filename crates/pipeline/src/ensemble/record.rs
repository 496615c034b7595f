//! One realization's record, `realizations/seed-N/record.json`: written last, atomically, so
//! that its presence says the realization is done. It holds everything the summary needs (the
//! metrics report, the spring discharges, the probability cells, the footprint columns of the
//! map rasters), so that the realization's
//! artifacts can go, and records from several machines can be merged.
//!
//! A record carries the ensemble's key: a record of another scene or other settings is not
//! this ensemble's and the realization runs again. A failed realization is recorded with its
//! error; it is final when the scene or an artifact is at fault (the same seed fails the same
//! way), and runs again on the next run when karstgen or the machine failed.

use std::path::{Path, PathBuf};

use serde::{Deserialize, Serialize};

use karst_export::rasters::Columns;
use karst_metrics::MetricsReport;

/// One realization of an ensemble.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Record {
    pub seed: u64,
    /// The ensemble's key ([`super::Plan::key`]).
    pub key: String,
    #[serde(flatten)]
    pub outcome: Outcome,
}

/// What became of a realization.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(tag = "status", rename_all = "snake_case")]
pub enum Outcome {
    Complete(Box<Figures>),
    Failed {
        error: String,
        /// True when karstgen or the machine failed: the next run tries again.
        retry: bool,
    },
}

/// What the summary takes from a complete realization.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Figures {
    /// The metrics report of its network (water types filled when hydro ran).
    pub report: MetricsReport,
    /// Every spring's discharge, when hydro ran.
    pub springs: Vec<SpringDischarge>,
    /// Sorted indices of the probability-grid cells its conduits pass through.
    pub cells: Vec<u32>,
    /// The depth spans of its conduits over each pixel of the map grid (`maps.rs`); empty in
    /// records of ensembles without one.
    #[serde(default)]
    pub columns: Columns,
}

/// The water leaving one spring.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct SpringDischarge {
    pub name: String,
    /// Flow, hydro's network units.
    pub flow: f64,
    /// Discharge, m³/s (`hydro.total_discharge` shared in proportion to the flow).
    pub discharge: f64,
}

impl Record {
    /// The record file of `seed` under the ensemble folder `out`.
    pub fn path(out: &Path, seed: u64) -> PathBuf {
        realization_dir(out, seed).join("record.json")
    }

    /// Reads a record; `None` when missing or unreadable (an interrupted write leaves none).
    pub fn read(path: &Path) -> Option<Record> {
        serde_json::from_slice(&std::fs::read(path).ok()?).ok()
    }

    /// Writes the record atomically.
    pub fn write(&self, out: &Path) -> std::io::Result<()> {
        let bytes = serde_json::to_vec(self).map_err(std::io::Error::other)?;
        karst_artifact::atomic::write_bytes(&Record::path(out, self.seed), &bytes)
    }

    /// True when the realization needs no more work for the ensemble of `key`.
    pub fn is_final(&self, key: &str) -> bool {
        self.key == key && !matches!(self.outcome, Outcome::Failed { retry: true, .. })
    }
}

/// The folder of one realization.
pub fn realization_dir(out: &Path, seed: u64) -> PathBuf {
    out.join("realizations").join(format!("seed-{seed}"))
}

/// Every record under `out/realizations/` of the ensemble `key`, by seed.
pub fn read_all(out: &Path, key: &str) -> Vec<Record> {
    let Ok(entries) = std::fs::read_dir(out.join("realizations")) else {
        return Vec::new();
    };
    let mut records: Vec<Record> = entries
        .filter_map(|e| Record::read(&e.ok()?.path().join("record.json")))
        .filter(|r| r.key == key)
        .collect();
    records.sort_by_key(|r| r.seed);
    records
}
