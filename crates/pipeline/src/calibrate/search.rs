//! A calibration as a sequence of steps, so that the candidates can be evaluated anywhere: in
//! this process ([`super::run`], rayon) or as tasks on other machines (the Python package on
//! Dask). [`Search::ask`] gives the next generation (first the scene itself, then CMA-ES's
//! candidates) until the budget would be exceeded, [`Search::tell`] takes their metrics on
//! every seed, and [`Search::finish`] writes the outputs. The steps depend only on the metrics
//! told, so a calibration gives the same candidates wherever they ran.

use std::time::Instant;

use karst_scene::Scene;
use karst_scene::params::CalibrateParams;
use karst_scene::rng::Random;
use karst_stage::StageError;

use super::cmaes::Cmaes;
use super::evaluate::{MetricVector, Runner};
use super::objective::{Objective, median};
use super::optimiser::{Optimiser, Start};
use super::outputs::{self, Candidate, Outcome};
use super::space::Space;
use super::target::{self, Aim, Target};
use super::{CalibrateError, Evaluated, verdict};
use crate::scene::SceneFile;

/// What the last [`Search::ask`] proposed, waiting for its metrics.
enum Asked {
    Nothing,
    /// The scene itself (generation 0).
    Scene,
    /// A generation of the optimiser: its step size and the candidates' parameter values.
    Generation {
        sigma: f64,
        values: Vec<Vec<f64>>,
    },
}

/// A calibration in progress.
pub struct Search<O: Optimiser = Cmaes> {
    scene: SceneFile,
    /// The scene's text, which the calibrated scene edits.
    text: String,
    config: CalibrateParams,
    space: Space,
    target: Target,
    /// The aim, as the calibrated scene records it (None: the scene's own, kept).
    aim: Option<Aim>,
    objective: Objective,
    seeds: Vec<u64>,
    es: O,
    candidates: Vec<Candidate>,
    generation: usize,
    asked: Asked,
    stopped_by: Option<&'static str>,
    started: Instant,
    runner: Option<Runner>,
}

impl Search<Cmaes> {
    /// A CMA-ES calibration of `scene` (whose text is `text`) towards `aim`, or towards the
    /// target its `[calibrate]` names when `aim` is None.
    pub fn new(scene: SceneFile, text: String, aim: Option<Aim>) -> Result<Search<Cmaes>, StageError> {
        Search::with(scene, text, aim, Cmaes::from_start)
    }
}

impl<O: Optimiser> Search<O> {
    /// The calibration with the optimiser `search` makes from the start of the search.
    pub fn with(
        scene: SceneFile,
        text: String,
        aim: Option<Aim>,
        search: impl FnOnce(Start) -> O,
    ) -> Result<Search<O>, StageError> {
        let path = scene.path.display().to_string();
        let config = scene.scene.calibrate().clone().ok_or_else(|| {
            StageError::input(format!(
                "{path}: no [calibrate] section: declare the parameters to search and their box (docs/calibrate.md)"
            ))
        })?;
        if config.parameters.is_empty() {
            return Err(StageError::input(format!(
                "{path}: calibrate.parameters is empty: list the parameters to search (docs/calibrate.md)"
            )));
        }
        let resolved = aim.clone().or_else(|| target::of_scene(&scene.scene)).ok_or_else(|| {
            StageError::input(format!(
                "{path}: no calibration target: give --like NAME or --target CAVE, or name one in \
                 [calibrate] (`like = \"NAME\"` or `target = \"FILE\"`)"
            ))
        })?;
        let target = target::read(&resolved)?;
        let seeds = seeds(&scene, &config)?;
        let space = Space::new(&config);
        let es = search(Start {
            mean: space.start(&scene.scene),
            sigma: config.step,
            population: config.population,
            random: Random::stream(scene.scene.seed(), "calibrate", "cmaes"),
        });
        Ok(Search {
            objective: Objective::new(target.metrics),
            text,
            config,
            space,
            target,
            aim,
            seeds,
            es,
            candidates: Vec::new(),
            generation: 0,
            asked: Asked::Nothing,
            stopped_by: None,
            started: Instant::now(),
            runner: None,
            scene,
        })
    }

    /// The seeds every candidate runs on.
    pub fn seeds(&self) -> &[u64] {
        &self.seeds
    }

    /// The scene calibrated.
    pub fn scene(&self) -> &SceneFile {
        &self.scene
    }

    /// The parameters searched, `section.field`, in the box's order.
    pub fn names(&self) -> Vec<&'static str> {
        self.space.dimensions.iter().map(|d| d.parameter.name).collect()
    }

    /// The budget in candidates, when there is one.
    pub fn evaluation_budget(&self) -> Option<usize> {
        self.config.evaluation_budget()
    }

    /// The length of a progress bar: runs (candidate × seed) against an evaluation budget,
    /// seconds against a budget in minutes.
    pub fn progress_length(&self) -> u64 {
        match self.config.evaluation_budget() {
            Some(b) => (b * self.config.seeds) as u64,
            None => (self.config.minutes.unwrap_or(0.0) * 60.0).ceil() as u64,
        }
    }

    /// The runner of this process, prepared on first use (the seeds' samples and cost graphs).
    pub fn runner(&mut self) -> Result<&Runner, StageError> {
        if self.runner.is_none() {
            let runner = Runner::new(&self.scene.scene, self.seeds.clone(), &self.space.sections())
                .map_err(|e| StageError::input(format!("{}: {e}", self.scene.path.display())))?;
            self.runner = Some(runner);
        }
        Ok(self.runner.as_ref().expect("prepared above"))
    }

    /// The next generation's parameter values: None for the scene itself (the first call), the
    /// optimiser's candidates after; None when the budget is spent.
    pub fn ask_values(&mut self) -> Option<Vec<Option<Vec<f64>>>> {
        if self.candidates.is_empty() {
            self.asked = Asked::Scene;
            return Some(vec![None]);
        }
        let budget = self.config.evaluation_budget();
        if budget.is_some_and(|b| self.candidates.len() + self.es.lambda() > b) {
            self.stopped_by = Some("evaluations");
            return None;
        }
        if self.config.minutes.is_some_and(|m| self.started.elapsed().as_secs_f64() >= m * 60.0) {
            self.stopped_by = Some("minutes");
            return None;
        }
        self.generation += 1;
        let sigma = self.es.sigma();
        let values: Vec<Vec<f64>> = self.es.ask().iter().map(|p| self.space.values(p)).collect();
        self.asked = Asked::Generation { sigma, values: values.clone() };
        Some(values.into_iter().map(Some).collect())
    }

    /// The next generation's scenes (see [`Search::ask_values`]).
    pub fn ask(&mut self) -> Option<Vec<Scene>> {
        let values = self.ask_values()?;
        Some(values.iter().map(|v| self.scene_of(v.as_deref())).collect())
    }

    /// The scene with `values` set (None: the scene itself).
    pub fn scene_of(&self, values: Option<&[f64]>) -> Scene {
        match values {
            Some(values) => self.space.apply(&self.scene.scene, values),
            None => self.scene.scene.clone(),
        }
    }

    /// The metrics of the generation last asked, `[candidate][seed]` (or why a run failed).
    pub fn tell(&mut self, runs: Vec<Vec<Result<MetricVector, CalibrateError>>>) -> Result<(), StageError> {
        let results: Vec<Evaluated> = runs.into_iter().map(|r| summarise(&self.objective, r)).collect();
        match std::mem::replace(&mut self.asked, Asked::Nothing) {
            Asked::Nothing => {
                Err(StageError::failure("calibration: metrics told without a generation asked"))
            }
            Asked::Scene => {
                let before = results.into_iter().next().ok_or_else(|| {
                    StageError::failure("calibration: no metrics told for the scene itself")
                })?;
                if let Some(why) = &before.failure {
                    return Err(StageError::input(format!(
                        "{}: the scene itself fails: {why}",
                        self.scene.path.display()
                    )));
                }
                let values = self.space.current(&self.scene.scene);
                let sigma = self.config.step;
                self.candidates.push(Candidate { generation: 0, index: 0, sigma, values, evaluated: before });
                Ok(())
            }
            Asked::Generation { sigma, values } => {
                if results.len() != values.len() {
                    return Err(StageError::failure(format!(
                        "calibration: {} candidates asked, {} told",
                        values.len(),
                        results.len()
                    )));
                }
                self.es.tell(&results.iter().map(|r| r.distance).collect::<Vec<_>>());
                let generation = self.generation;
                for (index, (values, evaluated)) in values.into_iter().zip(results).enumerate() {
                    let values = values.into_iter().map(Some).collect();
                    self.candidates.push(Candidate { generation, index, sigma, values, evaluated });
                }
                Ok(())
            }
        }
    }

    /// Every candidate so far, the scene itself first.
    pub fn candidates(&self) -> &[Candidate] {
        &self.candidates
    }

    /// Writes the outputs into `out` and returns the summary: one line, then the best scene's
    /// verdict against the target and its hints.
    pub fn finish(&mut self, out: &std::path::Path) -> Result<String, StageError> {
        if self.candidates.is_empty() {
            return Err(StageError::failure("calibration: finished before the scene itself was evaluated"));
        }
        let outcome = Outcome {
            scene: &self.scene,
            scene_text: &self.text,
            config: &self.config,
            space: &self.space,
            target: &self.target,
            aim: self.aim.as_ref(),
            seeds: &self.seeds,
            candidates: &self.candidates,
            generations: self.generation,
            population: self.es.lambda(),
            stopped_by: self.stopped_by.unwrap_or("evaluations"),
        };
        outputs::write(out, &outcome)?;
        let (before, best) = (outcome.before().evaluated.distance, outcome.best());
        let after = best.evaluated.distance;
        let head = format!(
            "calibrated {} to {}: distance {before:.4} → {after:.4} ({:.0} % less), {} candidates × {} seeds in {:.0} s → {}",
            self.scene.path.display(),
            self.target.name,
            100.0 * (1.0 - after / before),
            self.candidates.len(),
            self.config.seeds,
            self.started.elapsed().as_secs_f64(),
            out.display()
        );
        let best_scene = match best.generation {
            0 => self.scene.scene.clone(),
            _ => self
                .space
                .apply(&self.scene.scene, &best.values.iter().map(|v| v.unwrap_or(0.0)).collect::<Vec<_>>()),
        };
        let metrics = best.evaluated.metrics;
        let derived = self.runner()?.derived(&best_scene).unwrap_or_default();
        let lines = verdict::lines(&metrics, &best_scene, &derived, &self.target);
        Ok(std::iter::once(head).chain(lines).collect::<Vec<_>>().join("\n"))
    }
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
