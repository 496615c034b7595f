//! Running the pipeline like make: a stage runs when its artifact is missing or its key
//! differs from the key it would write now (stage, producer version, the scene sections it
//! reads, its inputs' payload hashes); otherwise it is up to date.

use std::path::Path;
use std::time::Instant;

use karst_artifact::stages::{producer, stage_key};
use karst_artifact::{InputRef, StageId, read_header};
use karst_stage::{Handoff, Job, StageError};

use crate::budget::OutputBudget;
use crate::registry;
use crate::scene::SceneFile;

/// Which stages to run.
#[derive(Debug, Clone, Default)]
pub struct Selection {
    /// Run this stage and every later one, even when up to date.
    pub from: Option<StageId>,
    /// Run only this stage, even when up to date.
    pub only: Option<StageId>,
    /// Stop after this stage.
    pub to: Option<StageId>,
    /// Run every stage, even when up to date.
    pub force: bool,
    /// What the outputs may take (`--budget`): the mesher holds its estimate to it (set on the
    /// run's scene) and the export its own, before either writes anything.
    pub budget: OutputBudget,
}

/// What happened to one stage.
#[derive(Debug, Clone, PartialEq)]
pub enum Outcome {
    /// The stage ran: its headline and notes.
    Ran {
        headline: String,
        notes: Vec<String>,
    },
    UpToDate,
    Skipped,
}

/// One line of the run report.
#[derive(Debug, Clone)]
pub struct StageReport {
    pub stage: StageId,
    pub outcome: Outcome,
    pub seconds: f64,
}

impl StageReport {
    /// The line printed for it: name, status, seconds, headline; then one indented line per
    /// note of the stage.
    pub fn line(&self) -> String {
        let (status, detail, notes) = match &self.outcome {
            Outcome::Ran { headline, notes } => ("ran", headline.as_str(), notes.as_slice()),
            Outcome::UpToDate => ("up to date", "", &[][..]),
            Outcome::Skipped => ("skipped", "", &[][..]),
        };
        let mut line = format!("{:<10} {:<11} {:>7.2} s  {detail}", self.stage.name(), status, self.seconds)
            .trim_end()
            .to_string();
        for note in notes {
            line.push_str(&format!("\n{:<10} note: {note}", ""));
        }
        line
    }
}

/// Runs the pipeline on `scene` into `out`, calling `report` after each stage.
pub fn run(
    scene: &SceneFile,
    out: &Path,
    selection: &Selection,
    report: &mut dyn FnMut(&StageReport),
) -> Result<Vec<StageReport>, StageError> {
    std::fs::create_dir_all(out).map_err(|e| {
        StageError::failure(format!("{}: cannot create the output folder: {e}", out.display()))
    })?;
    // One run writes into a folder at a time; what a killed run left half-written goes.
    let _lock = karst_artifact::lock_output(out)?;
    karst_stage::runner::sweep_leftovers(out);
    karst_stage::run_dir::record_scene(out, &scene.path).map_err(|e| {
        StageError::failure(format!("{}: cannot record the scene's path: {e}", out.display()))
    })?;
    // Each stage takes the payloads it reads from the stage before it when they are still in
    // memory, instead of reading back the artifacts just written.
    let handoff = Handoff::new();
    let mut held = scene.scene.clone();
    held.set_output_budget(selection.budget);
    let job = Job { handoff: Some(&handoff), ..Job::new(&scene.path, &held, out) };
    let mut reports = Vec::new();
    let mut stages = StageId::ALL.into_iter().peekable();
    while let Some(stage) = stages.next() {
        handoff.begin(stage);
        let plan = plan_of(&job, stage, selection);
        // The next stage runs beside this one when both run and it reads nothing this one
        // writes (the survey beside the mesher): its inputs are final already, and the two
        // share the threads, each filling the other's serial moments.
        let beside = stages.next_if(|&next| {
            plan == Plan::Run && may_run_beside(stage, next) && plan_of(&job, next, selection) == Plan::Run
        });
        let (first, second) = match beside {
            None => (timed(|| execute(&job, stage, plan, selection)), None),
            Some(next) => std::thread::scope(|scope| {
                let second = scope.spawn(|| timed(|| execute(&job, next, Plan::Run, selection)));
                let first = timed(|| execute(&job, stage, plan, selection));
                (first, Some(second.join().unwrap_or_else(|panic| std::panic::resume_unwind(panic))))
            }),
        };
        for (stage, (outcome, seconds)) in std::iter::once((stage, first)).chain(beside.zip(second)) {
            let line = StageReport { stage, outcome: outcome?, seconds };
            report(&line);
            reports.push(line);
        }
    }
    Ok(reports)
}

/// Whether `next` may run beside `stage`: it reads nothing `stage` writes.
fn may_run_beside(stage: StageId, next: StageId) -> bool {
    !next.inputs().contains(&stage)
}

/// What [`run`] does with a stage.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Plan {
    Skip,
    UpToDate,
    Run,
}

fn plan_of(job: &Job, stage: StageId, selection: &Selection) -> Plan {
    if !selected(stage, selection) {
        Plan::Skip
    } else if !forced(stage, selection) && up_to_date(job, stage) {
        Plan::UpToDate
    } else {
        Plan::Run
    }
}

/// Carries out `plan` for `stage`; the export first holds its estimate to the run's budget.
fn execute(job: &Job, stage: StageId, plan: Plan, selection: &Selection) -> Result<Outcome, StageError> {
    Ok(match plan {
        Plan::Skip => Outcome::Skipped,
        Plan::UpToDate => Outcome::UpToDate,
        Plan::Run => {
            if stage == StageId::Export {
                eprintln!("{}", crate::budget::check_export(job, selection.budget)?);
            }
            let ran = registry::stage(stage).run(job)?;
            Outcome::Ran { headline: ran.headline, notes: ran.notes }
        }
    })
}

/// `f`'s result and the seconds it took.
fn timed<T>(f: impl FnOnce() -> T) -> (T, f64) {
    let start = Instant::now();
    let value = f();
    (value, start.elapsed().as_secs_f64())
}

fn selected(stage: StageId, selection: &Selection) -> bool {
    selection.only.is_none_or(|only| only == stage) && selection.to.is_none_or(|to| stage <= to)
}

fn forced(stage: StageId, selection: &Selection) -> bool {
    selection.force || selection.only == Some(stage) || selection.from.is_some_and(|from| stage >= from)
}

/// The key `stage` would write now, if its inputs exist.
pub fn expected_key(job: &Job, stage: StageId) -> Option<String> {
    let inputs = stage
        .inputs()
        .iter()
        .map(|input| {
            let header = read_header(&job.artifact(*input)).ok()?;
            Some(InputRef { name: input.row().kind.into(), payload_blake3: header.payload_blake3 })
        })
        .collect::<Option<Vec<_>>>()?;
    let params = job.scene.sections_hash(registry::stage(stage).sections());
    let frame = job.scene.frame();
    Some(stage_key(stage, &producer(stage), registry::stage(stage).schema(), &params, frame, &inputs))
}

/// True when `stage`'s artifact exists and its key is the one it would write now.
pub fn up_to_date(job: &Job, stage: StageId) -> bool {
    let existing = read_header(&job.artifact(stage)).ok();
    match (existing, expected_key(job, stage)) {
        (Some(header), Some(key)) => header.key == key,
        _ => false,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn only_the_survey_runs_beside_the_stage_before_it() {
        let pairs: Vec<[StageId; 2]> =
            StageId::ALL.windows(2).filter(|w| may_run_beside(w[0], w[1])).map(|w| [w[0], w[1]]).collect();
        assert_eq!(pairs, [[StageId::Mesher, StageId::Survey]]);
    }

    #[test]
    fn a_stage_s_notes_follow_its_line() {
        let outcome =
            Outcome::Ran { headline: "2 falls".into(), notes: vec!["a lake".into(), "a fall".into()] };
        let report = StageReport { stage: StageId::Streams, outcome, seconds: 0.25 };
        assert_eq!(
            report.line(),
            "streams    ran            0.25 s  2 falls\n           note: a lake\n           note: a fall"
        );
    }
}
