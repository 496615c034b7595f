//! The coordinate frame of the exports. The artifacts hold local coordinates (metres, z up);
//! world coordinates are local + origin. Every writer takes its coordinates from
//! [`Frame::world`] (text formats, VTK) or writes local ones and records [`Frame::origin`]
//! (binary single-precision formats: glTF, PLY), so that a georeferenced origin, when the
//! artifacts carry one, is added here and nowhere else. Today the origin is (0, 0, 0).

use crate::Inputs;

/// Local-to-world translation.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Frame {
    origin: [f64; 3],
}

impl Frame {
    /// The frame of a run: the artifacts carry no origin yet, so local is world.
    pub fn of(_inputs: &Inputs) -> Frame {
        Frame { origin: [0.0; 3] }
    }

    /// The world position of a local point.
    pub fn world(&self, local: [f64; 3]) -> [f64; 3] {
        std::array::from_fn(|a| local[a] + self.origin[a])
    }

    /// The world position of a single-precision local point (mesh vertices).
    pub fn world_f32(&self, local: [f32; 3]) -> [f64; 3] {
        self.world(local.map(f64::from))
    }

    /// The world position of the local origin.
    pub fn origin(&self) -> [f64; 3] {
        self.origin
    }
}
