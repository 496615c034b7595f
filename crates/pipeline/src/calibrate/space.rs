//! The search space: the box of `[calibrate]`, mapped to the unit cube the optimiser works in.
//! A point's coordinate u in [0, 1] is the value min + u (max − min), rounded for integer
//! parameters; coordinates outside [0, 1] are reflected back first.

use karst_scene::params::{Bounds, CalibrateParams, Parameter, parameter};
use karst_scene::{Scene, Section};

use super::cmaes::reflect;

/// One dimension of the box.
pub struct Dimension {
    pub parameter: &'static Parameter,
    pub min: f64,
    pub max: f64,
    pub integer: bool,
}

/// The box.
pub struct Space {
    pub dimensions: Vec<Dimension>,
}

impl Space {
    /// The box of a validated `[calibrate]` section.
    pub fn new(config: &CalibrateParams) -> Space {
        let dimension = |b: &Bounds| {
            let parameter = parameter(&b.name).expect("a validated box names known parameters");
            Dimension { parameter, min: b.min, max: b.max, integer: b.is_integer(parameter) }
        };
        Space { dimensions: config.parameters.iter().map(dimension).collect() }
    }

    /// The scene sections the box changes.
    pub fn sections(&self) -> Vec<Section> {
        self.dimensions.iter().map(|d| d.parameter.section()).collect()
    }

    /// The scene's own values (None where unset).
    pub fn current(&self, scene: &Scene) -> Vec<Option<f64>> {
        self.dimensions.iter().map(|d| (d.parameter.get)(scene)).collect()
    }

    /// The scene's values in the unit cube, clamped into the box (unset: the box's minimum).
    pub fn start(&self, scene: &Scene) -> Vec<f64> {
        self.dimensions
            .iter()
            .zip(self.current(scene))
            .map(|(d, v)| ((v.unwrap_or(d.min) - d.min) / (d.max - d.min)).clamp(0.0, 1.0))
            .collect()
    }

    /// The parameter values of a point of the unit cube.
    pub fn values(&self, point: &[f64]) -> Vec<f64> {
        self.dimensions
            .iter()
            .zip(point)
            .map(|(d, &u)| {
                let v = d.min + reflect(u) * (d.max - d.min);
                if d.integer { v.round() } else { v }
            })
            .collect()
    }

    /// `scene` with `values` set.
    pub fn apply(&self, scene: &Scene, values: &[f64]) -> Scene {
        let mut scene = scene.clone();
        for (d, &v) in self.dimensions.iter().zip(values) {
            (d.parameter.set)(&mut scene, v);
        }
        scene
    }
}
