//! `karstgen calibrate SCENE --target CAVE` (or `--like NAME`): the network parameters of the
//! scene's `[calibrate]` box that bring its networks closest to a surveyed cave, the user's or a
//! published one.
//!
//! - [`target`]: the cave, read and characterised with karstnet's statistics, or a published
//!   network's statistics;
//! - [`objective`]: the distance of a network to it, each metric normalised by its real-cave
//!   range; a candidate's distance is the median over `calibrate.seeds` realizations;
//! - [`space`]: the box, as the unit cube the optimiser searches;
//! - [`optimiser`]: the ask-and-tell interface of the search, so that it can be replaced
//!   ([`run_with`]); [`cmaes`]: the one [`run`] uses, CMA-ES;
//! - [`evaluate`]: candidates run sampling, cost graph and skeleton in memory, in parallel;
//! - [`error`]: why a candidate cannot be evaluated or the calibrated scene written;
//! - [`outputs`]: what is written: the calibrated scene, `report.json`, `report.png`
//!   ([`chart`]) and `iterations.csv`; [`scene_edit`] writes the calibrated scene's text.
//!
//! The first candidate is the scene itself ("before"); then generation after generation of
//! CMA-ES until the budget (`calibrate.evaluations` candidates, `calibrate.minutes`) would be
//! exceeded. "After" is the best candidate seen. With a budget in evaluations, the same scene
//! and target give byte-identical outputs whatever the number of threads; a budget in minutes
//! stops after a number of generations that depends on the machine.

mod chart;
mod cmaes;
mod error;
mod evaluate;
mod objective;
pub mod optimiser;
mod outputs;
mod scene_edit;
mod search;
mod space;
mod target;
mod verdict;

pub use error::CalibrateError;
pub use evaluate::{MetricVector, Runner};
pub use search::Search;
pub use target::{Aim, SURVEYED, like_names};

use std::path::PathBuf;

use karst_stage::StageError;

use crate::scene::SceneFile;
use cmaes::Cmaes;
use optimiser::{Optimiser, Start};

/// What to run.
#[derive(Debug, Clone)]
pub struct CalibrateArgs {
    pub scene: PathBuf,
    /// The cave, or the published network; None: the one the scene's `[calibrate]` names.
    pub target: Option<Aim>,
    pub out: PathBuf,
}

/// One candidate's results over the seeds.
#[derive(Debug, Clone)]
pub struct Evaluated {
    /// Median distance over the seeds (+∞ when a seed failed).
    pub distance: f64,
    /// Median of each metric over the seeds.
    pub metrics: MetricVector,
    /// Why a seed failed.
    pub failure: Option<CalibrateError>,
}

/// Runs the calibration with CMA-ES and writes its outputs; returns a summary: one line, then
/// the best scene's verdict against the target.
pub fn run(args: &CalibrateArgs) -> Result<String, StageError> {
    run_with(args, Cmaes::from_start)
}

/// Runs the calibration with the optimiser `search` makes from the start of the search.
pub fn run_with<O: Optimiser>(
    args: &CalibrateArgs,
    search: impl FnOnce(Start) -> O,
) -> Result<String, StageError> {
    let scene = SceneFile::load(&args.scene)?;
    let text = std::fs::read_to_string(&args.scene)
        .map_err(|e| StageError::input(format!("{}: cannot read: {e}", args.scene.display())))?;
    let mut calibration = Search::with(scene, text, args.target.clone(), search)?;
    let bar = karst_stage::progress::bar(calibration.progress_length(), "calibrate");
    let (budget, started) = (calibration.evaluation_budget(), std::time::Instant::now());
    // The bar counts runs (candidate × seed) against an evaluation budget, seconds otherwise.
    let progress = || match budget {
        Some(_) => bar.inc(1),
        None => bar.set_position(started.elapsed().as_secs()),
    };
    while let Some(scenes) = calibration.ask() {
        let runs = calibration.runner()?.run(&scenes, &progress);
        calibration.tell(runs)?;
    }
    bar.finish_and_clear();
    calibration.finish(&args.out)
}
