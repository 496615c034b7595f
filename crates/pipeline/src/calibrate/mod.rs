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
mod space;
mod target;

pub use error::CalibrateError;
pub use target::{Aim, SURVEYED, like_names};

use std::path::PathBuf;
use std::time::Instant;

use karst_scene::Scene;
use karst_scene::params::CalibrateParams;
use karst_scene::rng::Random;
use karst_stage::StageError;

use crate::scene::SceneFile;
use cmaes::Cmaes;
use evaluate::{MetricVector, Runner};
use objective::{Objective, median};
use optimiser::{Optimiser, Start};
use outputs::{Candidate, Outcome};
use space::Space;

/// What to run.
#[derive(Debug, Clone)]
pub struct CalibrateArgs {
    pub scene: PathBuf,
    /// The cave, or the published network.
    pub target: Aim,
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

/// Runs the calibration with CMA-ES and writes its outputs; returns a one-line summary.
pub fn run(args: &CalibrateArgs) -> Result<String, StageError> {
    run_with(args, Cmaes::from_start)
}

/// Runs the calibration with the optimiser `search` makes from the start of the search.
pub fn run_with<O: Optimiser>(
    args: &CalibrateArgs,
    search: impl FnOnce(Start) -> O,
) -> Result<String, StageError> {
    let start = Instant::now();
    let scene = SceneFile::load(&args.scene)?;
    let config = scene.scene.calibrate().clone().ok_or_else(|| {
        StageError::input(format!(
            "{}: no [calibrate] section: declare the parameters to search and their box (docs/calibrate.md)",
            args.scene.display()
        ))
    })?;
    let target = target::read(&args.target)?;
    let objective = Objective::new(target.metrics);
    let space = Space::new(&config);
    let runner = Runner::new(&scene.scene, seeds(&scene, &config)?, &space.sections())
        .map_err(|e| StageError::input(format!("{}: {e}", args.scene.display())))?;
    let budget = config.evaluation_budget();
    // The bar counts runs (candidate × seed) against an evaluation budget, seconds otherwise.
    let length = match budget {
        Some(b) => (b * config.seeds) as u64,
        None => (config.minutes.unwrap_or(0.0) * 60.0).ceil() as u64,
    };
    let bar = karst_stage::progress::bar(length, "calibrate");
    let progress = || match budget {
        Some(_) => bar.inc(1),
        None => bar.set_position(start.elapsed().as_secs()),
    };
    let evaluate = |scenes: &[Scene]| -> Vec<Evaluated> {
        runner.run(scenes, &progress).into_iter().map(|runs| summarise(&objective, runs)).collect()
    };
    let before = evaluate(std::slice::from_ref(&scene.scene)).remove(0);
    if let Some(why) = &before.failure {
        return Err(StageError::input(format!("{}: the scene itself fails: {why}", args.scene.display())));
    }
    let current = space.current(&scene.scene);
    let mut candidates =
        vec![Candidate { generation: 0, index: 0, sigma: config.step, values: current, evaluated: before }];
    let mut es = search(Start {
        mean: space.start(&scene.scene),
        sigma: config.step,
        population: config.population,
        random: Random::stream(scene.scene.seed(), "calibrate", "cmaes"),
    });
    let mut generation = 0;
    let stopped_by = loop {
        if budget.is_some_and(|b| candidates.len() + es.lambda() > b) {
            break "evaluations";
        }
        if config.minutes.is_some_and(|m| start.elapsed().as_secs_f64() >= m * 60.0) {
            break "minutes";
        }
        generation += 1;
        let sigma = es.sigma();
        let drawn = es.ask();
        let values: Vec<Vec<f64>> = drawn.iter().map(|p| space.values(p)).collect();
        let scenes: Vec<Scene> = values.iter().map(|v| space.apply(&scene.scene, v)).collect();
        let results = evaluate(&scenes);
        es.tell(&results.iter().map(|r| r.distance).collect::<Vec<_>>());
        for (index, (values, evaluated)) in values.into_iter().zip(results).enumerate() {
            let values = values.into_iter().map(Some).collect();
            candidates.push(Candidate { generation, index, sigma, values, evaluated });
        }
    };
    bar.finish_and_clear();
    let outcome = Outcome {
        scene: &scene,
        config: &config,
        space: &space,
        target: &target,
        seeds: runner.seeds(),
        candidates: &candidates,
        generations: generation,
        population: es.lambda(),
        stopped_by,
    };
    outputs::write(&args.out, &outcome)?;
    let (before, after) = (outcome.before().evaluated.distance, outcome.best().evaluated.distance);
    Ok(format!(
        "calibrated {} to {}: distance {before:.4} → {after:.4} ({:.0} % less), {} candidates × {} seeds in {:.0} s → {}",
        args.scene.display(),
        target.name,
        100.0 * (1.0 - after / before),
        candidates.len(),
        config.seeds,
        start.elapsed().as_secs_f64(),
        args.out.display()
    ))
}

/// The calibration seeds: the scene's seed and the next ones.
fn seeds(scene: &SceneFile, config: &CalibrateParams) -> Result<Vec<u64>, StageError> {
    let first = scene.scene.seed();
    (0..config.seeds as u64)
        .map(|k| {
            first.checked_add(k).filter(|s| i64::try_from(*s).is_ok()).ok_or_else(|| {
                StageError::input(format!("{}: seed {first} + {k} is too large", scene.path.display()))
            })
        })
        .collect()
}

/// A candidate's distance and metrics: medians over its seeds, or +∞ and the reason when a seed
/// failed.
fn summarise(objective: &Objective, runs: Vec<Result<MetricVector, CalibrateError>>) -> Evaluated {
    let runs = match runs.into_iter().collect::<Result<Vec<_>, CalibrateError>>() {
        Ok(runs) => runs,
        Err(why) => {
            return Evaluated { distance: f64::INFINITY, metrics: [f64::NAN; 10], failure: Some(why) };
        }
    };
    let metrics = std::array::from_fn(|i| median(runs.iter().map(|m| m[i])));
    let distance = median(runs.iter().map(|m| objective.distance(m)));
    Evaluated { distance, metrics, failure: None }
}
