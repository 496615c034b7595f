//! The optimiser's interface: what the calibration loop asks of a search over the unit cube of
//! the box. [`super::run`] uses CMA-ES ([`super::cmaes::Cmaes`]); [`super::run_with`] takes any
//! other, so that a test can show the calibration's gain comes from the search (an optimiser
//! that only proposes the scene itself must not reach it).

use karst_scene::rng::Random;

/// An ask-and-tell minimiser: the caller evaluates each generation (in parallel), logs it and
/// stops on its own budget.
pub trait Optimiser {
    /// Candidates per generation.
    fn lambda(&self) -> usize;
    /// The current step size, in unit-cube coordinates (logged with each candidate).
    fn sigma(&self) -> f64;
    /// The next generation: points of the unit cube (reflected into it by the caller).
    fn ask(&mut self) -> Vec<Vec<f64>>;
    /// The objective values of the last generation asked, in its order (lower is better).
    fn tell(&mut self, values: &[f64]);
}

/// Where a search starts.
pub struct Start {
    /// The scene's own values in the unit cube.
    pub mean: Vec<f64>,
    /// `calibrate.step`.
    pub sigma: f64,
    /// `calibrate.population` (None: the optimiser's default).
    pub population: Option<usize>,
    /// The search's random stream, from the scene's seed.
    pub random: Random,
}
