//! What can be wrong with the inputs of the streams stage.

use thiserror::Error;

#[derive(Debug, Clone, PartialEq, Error)]
pub enum StreamsError {
    #[error(
        "hydro.json names spring \"{0}\", which is not a spring of the scene: rerun `cargo xtask run --from hydro`"
    )]
    UnknownSpring(String),
    #[error("hydro.json: spring \"{name}\" has flow {flow}: flows must be finite numbers ≥ 0")]
    BadFlow { name: String, flow: f64 },
    #[error("scene terrain: the height at [{x}, {y}] is {height}: the streams need a finite terrain")]
    Terrain { x: f64, y: f64, height: f64 },
    #[error("the surface network has a loop: an internal error of the streams stage")]
    Loop,
}

impl StreamsError {
    /// True when the error is about the scene file rather than hydro.json.
    pub fn concerns_scene(&self) -> bool {
        matches!(self, StreamsError::Terrain { .. })
    }
}
