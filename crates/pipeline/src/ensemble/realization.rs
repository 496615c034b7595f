//! One realization: the plan's stages on the scene with one seed, in
//! `realizations/seed-N/`, like `karstgen run` (a stage whose artifact is up to date is
//! skipped, so a realization interrupted halfway resumes where it stopped); then its figures,
//! the artifacts it does not keep removed, and its record written last.
//!
//! A failure (an error, or a panic of karstgen) is recorded, never propagated: one bad seed
//! does not stop an ensemble.

use std::panic::{AssertUnwindSafe, catch_unwind};
use std::path::Path;

use karst_artifact::{StageId, read_artifact};
use karst_hydro::Hydro;
use karst_metrics::MetricsReport;
use karst_skeleton::Skeleton;
use karst_stage::{Handoff, Job, StageError};

use super::Plan;
use super::record::{Figures, Outcome, Record, SpringDischarge, realization_dir};
use crate::options::OptionError;
use crate::{make, registry};

/// Which artifacts a realization keeps beside its record.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum Keep {
    /// Its whole folder (artifacts and side files).
    All,
    /// The artifacts of these stages; every other file goes.
    Stages(Vec<StageId>),
}

impl Keep {
    /// `all`, `none` or stage names separated by commas.
    pub fn parse(text: &str) -> Result<Keep, OptionError> {
        match text.trim() {
            "all" => Ok(Keep::All),
            "none" | "" => Ok(Keep::Stages(Vec::new())),
            list => list
                .split(',')
                .map(|name| {
                    StageId::from_name(name.trim()).ok_or_else(|| {
                        OptionError::new(
                            "--keep",
                            text,
                            format!("unknown stage \"{}\" (stage names, all or none)", name.trim()),
                        )
                    })
                })
                .collect::<Result<_, _>>()
                .map(Keep::Stages),
        }
    }
}

/// Runs the realization of `seed` under the ensemble folder `out` and writes its record;
/// fails only when the record cannot be written.
pub fn realize(plan: &Plan, out: &Path, seed: u64) -> Result<Record, StageError> {
    let outcome = match catch_unwind(AssertUnwindSafe(|| figures(plan, out, seed))) {
        Ok(Ok(figures)) => Outcome::Complete(Box::new(figures)),
        Ok(Err(e)) => Outcome::Failed { error: e.to_string(), retry: e.exit_code() != 2 },
        Err(panic) => {
            Outcome::Failed { error: format!("karstgen panicked: {}", panic_message(&*panic)), retry: true }
        }
    };
    let record = Record { seed, key: plan.key(), outcome };
    record
        .write(out)
        .map_err(|e| StageError::failure(format!("{}: {e}", Record::path(out, seed).display())))?;
    Ok(record)
}

fn figures(plan: &Plan, out: &Path, seed: u64) -> Result<Figures, StageError> {
    let dir = realization_dir(out, seed);
    std::fs::create_dir_all(&dir).map_err(|e| StageError::failure(format!("{}: {e}", dir.display())))?;
    let scene = plan.scene.with_seed(seed);
    let handoff = Handoff::new();
    let job = Job { handoff: Some(&handoff), ..Job::new(&scene.path, &scene.scene, &dir) };
    for &stage in plan.stages() {
        handoff.begin(stage);
        if !make::up_to_date(&job, stage) {
            registry::stage(stage).run(&job)?;
        }
    }
    let (report, springs, skeleton) = network_figures(&dir, plan.stages().contains(&StageId::Hydro))
        .map_err(|e| match e {
            StageError::BadInput(e) if e.downcast_ref::<karst_artifact::Error>().is_none() => {
                StageError::input(format!("seed {seed}: {e:#}"))
            }
            e => e,
        })?;
    let cells = plan.grid().cells_of(&skeleton);
    let hydro = match plan.stages().contains(&StageId::Hydro) {
        true => Some(read_artifact::<Hydro>(&dir.join(StageId::Hydro.file_name()))?.1),
        false => None,
    };
    let columns = plan.maps().columns(&scene.scene, &skeleton, hydro.as_ref())?;
    tidy(&dir, plan.keep()).map_err(|e| StageError::failure(format!("{}: {e}", dir.display())))?;
    Ok(Figures { report, springs, cells, columns })
}

/// The metrics report of the run in `dir` (with the water-type lengths when `hydro`), its
/// springs' discharges (when `hydro`) and its skeleton.
pub fn network_figures(
    dir: &Path,
    hydro: bool,
) -> Result<(MetricsReport, Vec<SpringDischarge>, Skeleton), StageError> {
    let (_, skeleton) = read_artifact::<Skeleton>(&dir.join(StageId::Skeleton.file_name()))?;
    let unusable = |e: &dyn std::fmt::Display| StageError::input(format!("{}: {e}", dir.display()));
    if !hydro {
        let report = karst_metrics::report(&skeleton).map_err(|e| unusable(&e))?;
        return Ok((report, Vec::new(), skeleton));
    }
    let (_, water) = read_artifact::<Hydro>(&dir.join(StageId::Hydro.file_name()))?;
    // The ensemble's figures are the underground network's: `surface` stays empty (an
    // ensemble may stop before the streams stage).
    let mut report = karst_metrics::report(&skeleton).map_err(|e| unusable(&e))?;
    report.water_types = karst_metrics::water_type_lengths(&skeleton, &water).map_err(|e| unusable(&e))?;
    Ok((report, springs(&water), skeleton))
}

/// Every spring's flow and discharge: hydro shares its total discharge among segments in
/// proportion to their flow, so a spring's discharge is its flow at the same rate.
fn springs(hydro: &Hydro) -> Vec<SpringDischarge> {
    let rate = hydro
        .conduits
        .iter()
        .flat_map(|c| &c.segments)
        .find(|s| s.flow > 0.0)
        .map_or(0.0, |s| s.discharge / s.flow);
    hydro
        .springs
        .iter()
        .map(|s| SpringDischarge { name: s.name.clone(), flow: s.flow, discharge: s.flow * rate })
        .collect()
}

/// Removes from the realization's folder everything but the kept artifacts.
fn tidy(dir: &Path, keep: &Keep) -> std::io::Result<()> {
    let Keep::Stages(stages) = keep else { return Ok(()) };
    let kept: Vec<&str> = stages.iter().map(|s| s.file_name()).collect();
    for entry in std::fs::read_dir(dir)? {
        let entry = entry?;
        if kept.iter().any(|k| entry.file_name() == **k) {
            continue;
        }
        if entry.file_type()?.is_dir() {
            std::fs::remove_dir_all(entry.path())?;
        } else {
            std::fs::remove_file(entry.path())?;
        }
    }
    Ok(())
}

fn panic_message(panic: &(dyn std::any::Any + Send)) -> String {
    panic
        .downcast_ref::<&str>()
        .map(|s| s.to_string())
        .or_else(|| panic.downcast_ref::<String>().cloned())
        .unwrap_or_else(|| "(no message)".into())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn keep_lists_parse() {
        assert_eq!(Keep::parse("all"), Ok(Keep::All));
        assert_eq!(Keep::parse("none"), Ok(Keep::Stages(vec![])));
        assert_eq!(
            Keep::parse("skeleton, metrics"),
            Ok(Keep::Stages(vec![StageId::Skeleton, StageId::Metrics]))
        );
        assert!(Keep::parse("skeleton,bones").unwrap_err().to_string().contains("\"bones\""));
    }
}
