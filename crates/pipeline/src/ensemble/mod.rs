//! Ensembles: many realizations of one scene that differ only by seed, their summary and the
//! conduit probability (`karstgen ensemble`, and the Python package's `karstgen.ensemble`).
//!
//! A [`Plan`] fixes the scene, the stages each realization runs (`--to STAGE`: that stage and
//! those it needs; by default up to hydro, what the metrics read), the probability grid and the
//! artifacts kept. Its key (the scene without its seed, data files included, the stages, the
//! grid and karstgen's version) marks every record, so that a folder never mixes ensembles.
//!
//! The ensemble folder:
//!
//! - `ensemble.json`: the plan (key, scene, stages, grid), written first;
//! - `realizations/seed-N/record.json`: one record per realization (see [`record`]), with the
//!   artifacts it keeps beside it;
//! - `metrics.csv` (one row per complete realization, by seed), `summary.csv` (min, mean, max,
//!   defined values, real-cave ranges and the fraction inside them), `failures.csv` (seed and
//!   error of each failed realization): see [`table`];
//! - `probability.vti`: the conduit probability as one VTK volume (ParaView);
//!   `probability/z-NNN.exr` the same, one horizontal slice per file, and `probability/grid.json`
//!   placing them; `probability-top.png`, the top view as a map;
//! - `probability.tif` and `mean-depth.tif`: the same probability as GeoTIFF map rasters on
//!   the grid of the single run's rasters, for a GIS (see [`maps`]).
//!
//! Running is resumable: a realization whose record is final is not run again, and the summary
//! covers every record of the folder, so seed ranges run one after the other, or on several
//! machines and then merged ([`merge`]), give the same outputs as one run. Records are gathered
//! in seed order and the grid holds integer counts, so the outputs are byte-identical whatever
//! the number of threads or processes.

mod grid;
pub mod maps;
mod picture;
pub mod realization;
pub mod record;
mod seeds;
pub mod table;
mod volume;

use std::path::{Path, PathBuf};

use rayon::prelude::*;
use serde::{Deserialize, Serialize};

use karst_artifact::StageId;
use karst_stage::StageError;

use crate::scene::SceneFile;
pub use grid::Grid;
pub use maps::{MapGrid, parse_depth_band};
pub use realization::{Keep, realize};
pub use record::{Figures, Outcome, Record};
pub use seeds::{first_n, parse_seeds};
pub use table::Table;
pub use volume::write_vti;

/// The stage an ensemble runs to by default: hydro, the last one the metrics read.
pub const DEFAULT_TO: StageId = StageId::Hydro;
/// The default edge of a probability-grid cell, metres.
pub const DEFAULT_CELL: f64 = 10.0;

/// What every realization of an ensemble shares.
#[derive(Debug, Clone)]
pub struct Plan {
    pub scene: SceneFile,
    stages: Vec<StageId>,
    grid: Grid,
    maps: MapGrid,
    keep: Keep,
    key: String,
}

/// `ensemble.json`: the plan, for people and for merging.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Definition {
    pub key: String,
    pub scene: PathBuf,
    pub name: String,
    pub stages: Vec<String>,
    pub grid: Grid,
    /// The map rasters' grid (absent from ensembles made before them: no GeoTIFFs).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub maps: Option<MapGrid>,
    pub karstgen: String,
}

impl Plan {
    /// The plan of `scene` run to `to` (None: every stage) with `cell`-metre probability cells.
    pub fn new(scene: SceneFile, to: Option<StageId>, cell: f64, keep: Keep) -> Result<Plan, StageError> {
        let stages = match to {
            Some(stage) => needed(stage),
            None => StageId::ALL.to_vec(),
        };
        if !stages.contains(&StageId::Skeleton) {
            return Err(StageError::input(format!(
                "ensemble: --to {}: the summary needs the skeleton (--to skeleton or later)",
                to.map_or("all", |s| s.name())
            )));
        }
        let grid = Grid::new(&scene.scene, cell).map_err(|e| StageError::input(format!("ensemble: {e}")))?;
        let maps = MapGrid::of(&scene.scene)?;
        let mut without_seed = serde_json::to_value(&scene.scene)
            .map_err(|e| StageError::failure(format!("{}: {e}", scene.path.display())))?;
        if let Some(table) = without_seed.as_object_mut() {
            table.remove("seed");
        }
        let names: Vec<&str> = stages.iter().map(|s| s.name()).collect();
        let parts = [
            env!("CARGO_PKG_VERSION").to_string(),
            without_seed.to_string(),
            names.join(","),
            serde_json::to_string(&grid).unwrap_or_default(),
            serde_json::to_string(&maps).unwrap_or_default(),
        ];
        let key = karst_artifact::hash::hex_of_parts(parts.iter().map(|p| p.as_bytes()));
        Ok(Plan { scene, stages, grid, maps, keep, key })
    }

    /// The stages each realization runs, in order.
    pub fn stages(&self) -> &[StageId] {
        &self.stages
    }

    pub fn grid(&self) -> &Grid {
        &self.grid
    }

    /// The map rasters' grid.
    pub fn maps(&self) -> &MapGrid {
        &self.maps
    }

    pub fn keep(&self) -> &Keep {
        &self.keep
    }

    /// The ensemble's key, in every record.
    pub fn key(&self) -> String {
        self.key.clone()
    }

    /// `ensemble.json`'s content.
    pub fn definition(&self) -> Definition {
        Definition {
            key: self.key.clone(),
            scene: self.scene.path.clone(),
            name: self.scene.scene.name().to_string(),
            stages: self.stages.iter().map(|s| s.name().to_string()).collect(),
            grid: self.grid.clone(),
            maps: Some(self.maps.clone()),
            karstgen: env!("CARGO_PKG_VERSION").to_string(),
        }
    }

    /// Makes `out` this plan's folder: writes `ensemble.json`, or checks that the one there is
    /// this plan's.
    pub fn prepare(&self, out: &Path) -> Result<(), StageError> {
        let path = out.join("ensemble.json");
        if let Ok(existing) = read_definition(out)
            && existing.key != self.key
        {
            return Err(StageError::input(format!(
                "{}: the folder holds an ensemble of another scene or other settings ({}, stages {}, {} m cells); \
                 choose another --out or remove it",
                path.display(),
                existing.scene.display(),
                existing.stages.join(", "),
                existing.grid.cell
            )));
        }
        let text = serde_json::to_string_pretty(&self.definition()).unwrap_or_default() + "\n";
        crate::scene::write_if_changed(&path, text.as_bytes())
    }

    /// The seeds of `seeds` whose realization still needs work in `out`.
    pub fn pending(&self, out: &Path, seeds: &[u64]) -> Vec<u64> {
        seeds
            .iter()
            .copied()
            .filter(|&s| !Record::read(&Record::path(out, s)).is_some_and(|r| r.is_final(&self.key)))
            .collect()
    }
}

/// `stage` and every stage it needs, in table order.
fn needed(stage: StageId) -> Vec<StageId> {
    let mut need = vec![stage];
    let mut i = 0;
    while i < need.len() {
        for &input in need[i].inputs() {
            if !need.contains(&input) {
                need.push(input);
            }
        }
        i += 1;
    }
    need.sort();
    need
}

fn read_definition(dir: &Path) -> Result<Definition, StageError> {
    let path = dir.join("ensemble.json");
    let text = std::fs::read(&path)
        .map_err(|e| StageError::input(format!("{}: not an ensemble folder: {e}", path.display())))?;
    serde_json::from_slice(&text).map_err(|e| StageError::input(format!("{}: {e}", path.display())))
}

/// What a run or a merge did, and the ensemble's summary.
#[derive(Debug, Clone)]
pub struct Summary {
    /// Realizations run now (the others were complete already).
    pub ran: usize,
    /// Complete realizations in the folder.
    pub complete: usize,
    /// Seed and error of each failed realization.
    pub failures: Vec<(u64, String)>,
    pub table: Table,
    pub grid: Grid,
    /// Realizations with a conduit in each cell.
    pub counts: Vec<u32>,
}

impl Summary {
    /// One line for people.
    pub fn line(&self, out: &Path) -> String {
        let seeds = match (self.table.rows.first(), self.table.rows.last()) {
            (Some(a), Some(b)) => format!(", seeds {}..={}", a[0], b[0]),
            _ => String::new(),
        };
        format!(
            "{} realizations complete{seeds} ({} run now), {} failed → {}",
            self.complete,
            self.ran,
            self.failures.len(),
            out.display()
        )
    }
}

/// Runs the realizations of `seeds` still pending in `out`, in parallel, then summarises the
/// folder (`band`: the depth band of `probability.tif`, metres below ground; None: any depth).
pub fn run(plan: &Plan, out: &Path, seeds: &[u64], band: Option<[f64; 2]>) -> Result<Summary, StageError> {
    plan.prepare(out)?;
    let pending = plan.pending(out, seeds);
    let bar = karst_stage::progress::bar(pending.len() as u64, "ensemble");
    let written: Result<Vec<Record>, StageError> = pending
        .par_iter()
        .map(|&seed| {
            let record = realize(plan, out, seed);
            bar.inc(1);
            record
        })
        .collect();
    bar.finish_and_clear();
    written?;
    let mut summary = summarize(out, band)?;
    summary.ran = pending.len();
    Ok(summary)
}

/// Gathers the records of the ensemble folders `dirs` (one plan, several seed ranges) into
/// `out` and summarises it (`band` as for [`run`]).
pub fn merge(dirs: &[PathBuf], out: &Path, band: Option<[f64; 2]>) -> Result<Summary, StageError> {
    let definitions = dirs.iter().map(|d| read_definition(d)).collect::<Result<Vec<_>, _>>()?;
    let Some(first) = definitions.first() else {
        return Err(StageError::input("ensemble merge: name at least one ensemble folder"));
    };
    if let Some((dir, other)) = dirs.iter().zip(&definitions).find(|(_, d)| d.key != first.key) {
        return Err(StageError::input(format!(
            "ensemble merge: {} is an ensemble of another scene or other settings than {} ({} vs {})",
            dir.display(),
            dirs[0].display(),
            other.scene.display(),
            first.scene.display()
        )));
    }
    let text = serde_json::to_string_pretty(first).unwrap_or_default() + "\n";
    let target = out.join("ensemble.json");
    if read_definition(out).is_ok_and(|d| d.key != first.key) {
        return Err(StageError::input(format!(
            "{}: the folder holds an ensemble of another scene or other settings",
            target.display()
        )));
    }
    crate::scene::write_if_changed(&target, text.as_bytes())?;
    for dir in dirs {
        for record in record::read_all(dir, &first.key) {
            let here = Record::read(&Record::path(out, record.seed));
            if here.is_some_and(|h| h.is_final(&first.key)) {
                continue;
            }
            record.write(out).map_err(|e| {
                StageError::failure(format!("{}: {e}", Record::path(out, record.seed).display()))
            })?;
        }
    }
    summarize(out, band)
}

/// Writes the summary outputs of the ensemble folder `out` from its records (`band`: the depth
/// band of `probability.tif`, metres below ground; None: any depth).
pub fn summarize(out: &Path, band: Option<[f64; 2]>) -> Result<Summary, StageError> {
    let definition = read_definition(out)?;
    let grid = definition.grid;
    let records = record::read_all(out, &definition.key);
    let mut complete = Vec::new();
    let mut failures = Vec::new();
    for r in &records {
        match &r.outcome {
            Outcome::Complete(f) if grid.holds(&f.cells) => complete.push((r.seed, &**f)),
            Outcome::Complete(_) => failures.push((r.seed, "its record names cells outside the grid".into())),
            Outcome::Failed { error, .. } => failures.push((r.seed, error.clone())),
        }
    }
    let table = table::table(&complete);
    let mut counts = vec![0u32; grid.cell_count()];
    for (_, f) in &complete {
        for &c in &f.cells {
            counts[c as usize] += 1;
        }
    }
    write_outputs(out, &grid, &table, &failures, &counts, &complete)?;
    if let Some(map) = &definition.maps {
        maps::write(out, map, &complete, band)?;
    }
    Ok(Summary { ran: 0, complete: complete.len(), failures, table, grid, counts })
}

fn write_outputs(
    out: &Path,
    grid: &Grid,
    table: &Table,
    failures: &[(u64, String)],
    counts: &[u32],
    complete: &[(u64, &Figures)],
) -> Result<(), StageError> {
    let write = |name: &str, bytes: &[u8]| {
        let path = out.join(name);
        karst_artifact::atomic::write_bytes(&path, bytes)
            .map_err(|e| StageError::failure(format!("{}: cannot write: {e}", path.display())))
    };
    let n = complete.len();
    write("metrics.csv", table::csv(table).as_bytes())?;
    write("summary.csv", table::summary(table).as_bytes())?;
    write("failures.csv", table::failures_csv(failures).as_bytes())?;
    let vti = out.join("probability.vti");
    karst_artifact::atomic::write_with(&vti, |w| write_vti(w, grid, counts, n))
        .map_err(|e| StageError::failure(format!("{}: cannot write: {e}", vti.display())))?;
    write("probability/grid.json", (grid.placement(n).to_string() + "\n").as_bytes())?;
    let probability = |c: u32| (f64::from(c) / n.max(1) as f64) as f32;
    for (z, layer) in counts.chunks(grid.layer()).enumerate() {
        let slice: Vec<f32> = layer.iter().map(|&c| probability(c)).collect();
        let bytes = picture::exr_slice(grid.dims[0], grid.dims[1], &slice)
            .map_err(|e| StageError::failure(format!("probability/z-{z:03}.exr: {e}")))?;
        write(&format!("probability/z-{z:03}.exr"), &bytes)?;
    }
    let mut columns = vec![0u32; grid.layer()];
    for (_, f) in complete {
        let mut touched: Vec<usize> = f.cells.iter().map(|&c| grid.column(c)).collect();
        touched.sort_unstable();
        touched.dedup();
        for c in touched {
            columns[c] += 1;
        }
    }
    let top: Vec<f64> = columns.iter().map(|&c| f64::from(c) / n.max(1) as f64).collect();
    let mut png = Vec::new();
    picture::top_view(grid, &top, n)
        .encode_png(&mut png)
        .map_err(|e| StageError::failure(format!("probability-top.png: {e}")))?;
    write("probability-top.png", &png)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_stage_needs_its_upstream_stages_only() {
        use StageId::*;
        assert_eq!(needed(Metrics), [Sampling, Costgraph, Skeleton, Hydro, Streams, Metrics]);
        assert_eq!(needed(Skeleton), [Sampling, Costgraph, Skeleton]);
        assert_eq!(needed(Mesher), [Sampling, Costgraph, Skeleton, Hydro, Streams, Sdf, Mesher]);
    }
}
