//! `[calibrate]`: the box of network parameters that `karstgen calibrate` searches, its budget,
//! and the network it aims at (`like`, a published network, or `target`, a surveyed cave's
//! file). Only the aim is read by a stage: the metrics stage reports a run's statistics against
//! it ([`CalibrateParams::aim`]); the box and the budget are read by no stage.
//!
//! ```toml
//! [calibrate]
//! like = "Sakany"      # or target = "caves/mine_nodes.dat"
//! seeds = 3            # realizations per candidate (seeds scene seed .. + 2); the median counts
//! evaluations = 200    # budget in candidates (each run on every seed)
//! minutes = 10         # and/or in wall-clock minutes
//!
//! [[calibrate.parameters]]
//! name = "skeleton.amplification_steps"
//! min = 0
//! max = 4
//! ```
//!
//! [`PARAMETERS`] lists every parameter that may be calibrated: the scene field it sets, the
//! values it accepts and whether it is an integer; a box outside those values, or naming a
//! parameter the scene's mode ignores, is refused with the field and the value.

use serde::{Deserialize, Serialize};

use crate::params::{CostModelKind, SkeletonMode};
use crate::validate::Checks;
use crate::{Scene, Section};

/// `[calibrate]`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct CalibrateParams {
    /// The published network the calibration aims at, by name (`karstgen calibrate --like`).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub like: Option<String>,
    /// The surveyed cave the calibration aims at: a karstnet `BASE_nodes.dat` (or `BASE`) or a
    /// GOCAD PLine `.pl`, relative to the scene's folder (`karstgen calibrate --target`).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub target: Option<String>,
    /// BLAKE3 of the target's file(s), filled when the scene is loaded, so that editing the
    /// cave makes the verdict stale.
    #[serde(default, skip_deserializing, skip_serializing_if = "String::is_empty")]
    pub target_content: String,
    /// `target` resolved against the scene's folder, filled when the scene is loaded.
    #[serde(skip)]
    pub target_path: Option<std::path::PathBuf>,
    /// Realizations per candidate (seeds scene seed, +1, …); the candidate's distance is the
    /// median over them.
    pub seeds: usize,
    /// Budget: candidates evaluated, the scene's own values included.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub evaluations: Option<usize>,
    /// Budget: minutes of wall-clock time; no generation starts after it.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub minutes: Option<f64>,
    /// Candidates per generation (CMA-ES λ); default 4 + ⌊3 ln n⌋ for n parameters.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub population: Option<usize>,
    /// Initial step size, as a fraction of each parameter's interval.
    pub step: f64,
    /// The box: one entry per parameter searched.
    pub parameters: Vec<Bounds>,
}

impl Default for CalibrateParams {
    fn default() -> Self {
        CalibrateParams {
            like: None,
            target: None,
            target_content: String::new(),
            target_path: None,
            seeds: 3,
            evaluations: None,
            minutes: None,
            population: None,
            step: 0.3,
            parameters: Vec::new(),
        }
    }
}

/// The interval searched for one parameter.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Bounds {
    /// The parameter, as `section.field` (see [`PARAMETERS`]).
    pub name: String,
    pub min: f64,
    pub max: f64,
    /// Whole numbers only; always so for integer parameters.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub integer: Option<bool>,
}

/// The budget when the section sets neither `evaluations` nor `minutes`.
pub const DEFAULT_EVALUATIONS: usize = 100;
/// At most this many seeds per candidate.
pub const MAX_SEEDS: usize = 64;

/// A scene parameter that calibration may set.
pub struct Parameter {
    /// `section.field`, as written in the scene.
    pub name: &'static str,
    /// Whole numbers only.
    pub integer: bool,
    /// Smallest and largest accepted values, and whether the smallest is excluded.
    pub lower: f64,
    pub lower_open: bool,
    pub upper: f64,
    /// The scene's current value (None when unset, e.g. `skeleton.tortuosity` absent).
    pub get: fn(&Scene) -> Option<f64>,
    /// Sets the value.
    pub set: fn(&mut Scene, f64),
    /// Why the scene's modes ignore the parameter, if they do.
    pub ignored: fn(&Scene) -> Option<&'static str>,
}

fn always_used(_: &Scene) -> Option<&'static str> {
    None
}

fn unless_gamma(scene: &Scene) -> Option<&'static str> {
    (scene.skeleton.mode != SkeletonMode::Gamma).then_some("it only acts when skeleton.mode = \"gamma\"")
}

fn unless_karstnsim(scene: &Scene) -> Option<&'static str> {
    (scene.skeleton.mode != SkeletonMode::Karstnsim)
        .then_some("it only acts when skeleton.mode = \"karstnsim\"")
}

fn unless_paris(scene: &Scene) -> Option<&'static str> {
    (scene.costgraph.model != CostModelKind::Paris2021)
        .then_some("it only acts when costgraph.model = \"paris2021\"")
}

fn unless_karstnsim_costs(scene: &Scene) -> Option<&'static str> {
    (scene.costgraph.model != CostModelKind::Karstnsim2024)
        .then_some("it only acts when costgraph.model = \"karstnsim2024\"")
}

/// A real parameter of `$section` field `$field` in `[$lower, $upper]` (`$open`: lower
/// excluded).
macro_rules! real {
    ($name:literal, $section:ident . $field:ident, $lower:expr, $open:expr, $upper:expr, $ignored:expr) => {
        Parameter {
            name: $name,
            integer: false,
            lower: $lower,
            lower_open: $open,
            upper: $upper,
            get: |s| Some(s.$section.$field as f64),
            set: |s, v| s.$section.$field = v,
            ignored: $ignored,
        }
    };
}

/// An integer parameter of `$section` field `$field` (type `$ty`) in `[$lower, $upper]`.
macro_rules! integer {
    ($name:literal, $section:ident . $field:ident : $ty:ty, $lower:expr, $upper:expr) => {
        Parameter {
            name: $name,
            integer: true,
            lower: $lower,
            lower_open: false,
            upper: $upper,
            get: |s| Some(s.$section.$field as f64),
            set: |s, v| s.$section.$field = v.round() as $ty,
            ignored: always_used,
        }
    };
}

const INF: f64 = f64::INFINITY;

/// Every parameter that may be calibrated: those that shape the network (sampling, cost graph,
/// skeleton). Ranges are the scene's own validation ranges.
pub const PARAMETERS: &[Parameter] = &[
    Parameter {
        name: "sampling.radius",
        integer: false,
        lower: 0.0,
        lower_open: true,
        upper: INF,
        get: |s| s.sampling.radius,
        set: |s, v| s.sampling.radius = Some(v),
        ignored: always_used,
    },
    integer!("costgraph.k", costgraph.k: usize, 1.0, crate::params::costgraph::MAX_K as f64),
    real!("costgraph.alpha_inception", costgraph.alpha_inception, 0.0, false, INF, unless_karstnsim_costs),
    real!("costgraph.alpha_fracture", costgraph.alpha_fracture, 0.0, false, INF, unless_karstnsim_costs),
    real!(
        "costgraph.alpha_water_table",
        costgraph.alpha_water_table,
        0.0,
        false,
        INF,
        unless_karstnsim_costs
    ),
    real!("costgraph.alpha_potential", costgraph.alpha_potential, 0.0, false, INF, unless_karstnsim_costs),
    real!(
        "costgraph.inception_distance",
        costgraph.inception_distance,
        0.0,
        true,
        INF,
        unless_karstnsim_costs
    ),
    real!("costgraph.w_distance", costgraph.w_distance, 0.0, false, INF, unless_paris),
    real!("costgraph.w_horizon", costgraph.w_horizon, 0.0, false, INF, unless_paris),
    real!("costgraph.w_fracture", costgraph.w_fracture, 0.0, false, INF, unless_paris),
    real!("costgraph.w_permeability", costgraph.w_permeability, 0.0, false, INF, unless_paris),
    real!("costgraph.horizon_distance", costgraph.horizon_distance, 0.0, true, INF, unless_paris),
    real!("skeleton.gamma", skeleton.gamma, 0.0, true, INF, unless_gamma),
    real!("skeleton.cohesion_vadose", skeleton.cohesion_vadose, 0.0, true, 1.0, unless_karstnsim),
    real!("skeleton.cohesion_phreatic", skeleton.cohesion_phreatic, 0.0, true, 1.0, unless_karstnsim),
    integer!("skeleton.amplification_steps", skeleton.amplification_steps: usize, 0.0, 50.0),
    Parameter {
        name: "skeleton.amplification_points",
        integer: true,
        lower: 0.0,
        lower_open: false,
        upper: 1000.0,
        get: |s| s.skeleton.amplification_points.map(|p| p as f64),
        set: |s, v| s.skeleton.amplification_points = Some(v.round() as usize),
        ignored: always_used,
    },
    real!("skeleton.dead_end_fraction", skeleton.dead_end_fraction, 0.0, false, 1.0, always_used),
    Parameter {
        name: "skeleton.tortuosity",
        integer: false,
        lower: 0.0,
        lower_open: false,
        upper: 1.0,
        get: |s| s.skeleton.tortuosity,
        set: |s, v| s.skeleton.tortuosity = Some(v),
        ignored: always_used,
    },
    integer!("skeleton.tortuosity_levels", skeleton.tortuosity_levels: u32, 0.0, 6.0),
];

/// The parameter called `name`.
pub fn parameter(name: &str) -> Option<&'static Parameter> {
    PARAMETERS.iter().find(|p| p.name == name)
}

impl Parameter {
    /// The scene section it lives in.
    pub fn section(&self) -> Section {
        let key = self.name.split_once('.').map_or(self.name, |(section, _)| section);
        Section::from_key(key).expect("every parameter names its section")
    }

    /// Whether `value` is accepted by the scene.
    pub fn accepts(&self, value: f64) -> bool {
        let above = if self.lower_open { value > self.lower } else { value >= self.lower };
        above && value <= self.upper && (!self.integer || value.fract() == 0.0)
    }

    fn describe_range(&self) -> String {
        let open = if self.lower_open { "(" } else { "[" };
        let upper = if self.upper.is_finite() { format!("{}]", self.upper) } else { "∞)".into() };
        let kind = if self.integer { "an integer in" } else { "in" };
        format!("{kind} {open}{}, {upper}", self.lower)
    }
}

impl Bounds {
    /// Whether the search keeps this parameter to whole numbers.
    pub fn is_integer(&self, parameter: &Parameter) -> bool {
        parameter.integer || self.integer == Some(true)
    }
}

/// What a scene's `[calibrate]` aims at, as the metrics stage reads it.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub enum Aim<'s> {
    /// `like = "NAME"`.
    Like(&'s str),
    /// `target = "FILE"`: the file as written, its path from the scene's folder and its BLAKE3.
    Target { file: &'s str, path: &'s std::path::Path, content: &'s str },
}

impl CalibrateParams {
    /// The network the section aims at, when it names one.
    pub fn aim(&self) -> Option<Aim<'_>> {
        if let Some(name) = &self.like {
            return Some(Aim::Like(name));
        }
        let file = self.target.as_deref()?;
        let path = self.target_path.as_deref().unwrap_or(std::path::Path::new(file));
        Some(Aim::Target { file, path, content: &self.target_content })
    }

    /// The budget in candidates, when one is set or neither budget is.
    pub fn evaluation_budget(&self) -> Option<usize> {
        match (self.evaluations, self.minutes) {
            (None, None) => Some(DEFAULT_EVALUATIONS),
            (evaluations, _) => evaluations,
        }
    }

    pub(crate) fn check(&self, scene: &Scene, c: &mut Checks) {
        if self.seeds == 0 || self.seeds > MAX_SEEDS {
            c.report("calibrate.seeds", format!("must be in [1, {MAX_SEEDS}], got {}", self.seeds));
        }
        if self.evaluations == Some(0) {
            c.report("calibrate.evaluations", "must be ≥ 1, got 0".into());
        }
        if let Some(minutes) = self.minutes {
            c.positive("calibrate.minutes", minutes);
        }
        if let Some(p) = self.population
            && p < 2
        {
            c.report("calibrate.population", format!("must be ≥ 2, got {p}"));
        }
        if c.finite("calibrate.step", &[self.step]) && !(self.step > 0.0 && self.step <= 1.0) {
            c.report("calibrate.step", format!("must be in (0, 1], got {}", self.step));
        }
        if self.like.is_some() && self.target.is_some() {
            c.report("calibrate.target", "give `like` or `target`, not both".into());
        }
        if self.like.as_deref().is_some_and(|l| l.trim().is_empty()) {
            c.report("calibrate.like", "is empty: name a published network or `surveyed`".into());
        }
        if self.parameters.is_empty() && self.aim().is_none() {
            c.report(
                "calibrate.parameters",
                "the box is empty: list at least one parameter (or name a `like` or `target` only)".into(),
            );
        }
        for (i, bounds) in self.parameters.iter().enumerate() {
            self.check_bounds(scene, i, bounds, c);
        }
    }

    fn check_bounds(&self, scene: &Scene, i: usize, bounds: &Bounds, c: &mut Checks) {
        let field = |f: &str| format!("calibrate.parameters[{i}].{f}");
        let Some(parameter) = parameter(&bounds.name) else {
            let names: Vec<&str> = PARAMETERS.iter().map(|p| p.name).collect();
            c.report(
                &field("name"),
                format!("unknown parameter \"{}\"; parameters: {}", bounds.name, names.join(", ")),
            );
            return;
        };
        if self.parameters[..i].iter().any(|b| b.name == bounds.name) {
            c.report(&field("name"), format!("\"{}\" is listed twice", bounds.name));
        }
        if let Some(why) = (parameter.ignored)(scene) {
            c.report(&field("name"), format!("\"{}\" has no effect on this scene: {why}", bounds.name));
        }
        if parameter.integer && bounds.integer == Some(false) {
            c.report(&field("integer"), format!("\"{}\" is an integer parameter", bounds.name));
        }
        let integer = bounds.is_integer(parameter);
        let mut ok = true;
        for (key, value) in [("min", bounds.min), ("max", bounds.max)] {
            if !c.finite(&field(key), &[value]) {
                ok = false;
            } else if !parameter.accepts(value) || (integer && value.fract() != 0.0) {
                c.report(
                    &field(key),
                    format!("{value}: {} must be {}", bounds.name, parameter.describe_range()),
                );
                ok = false;
            }
        }
        if ok && bounds.max <= bounds.min {
            c.report(
                &field("max"),
                format!("[{}, {}] is not an interval (max must be above min)", bounds.min, bounds.max),
            );
        }
    }
}
