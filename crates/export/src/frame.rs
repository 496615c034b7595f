//! The coordinate frame of the exports. The artifacts hold local coordinates (metres, z up);
//! world coordinates are local + origin. Every writer takes its coordinates from
//! [`Frame::world`] (text formats, VTK) or writes local ones and records [`Frame::origin`]
//! (glTF's single-precision buffers, under a root node translated by the origin), so that the
//! origin the artifacts record (the domain's `min` corner of a georeferenced scene) is added
//! here and nowhere else.

use crate::Inputs;

/// Local-to-world translation.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Frame {
    origin: [f64; 3],
}

impl Frame {
    /// The frame of a run: the origin its artifacts record.
    pub fn of(inputs: &Inputs) -> Frame {
        Frame { origin: inputs.frame.origin }
    }

    /// The frame whose local origin lies at `origin` in the world.
    pub fn new(origin: [f64; 3]) -> Frame {
        Frame { origin }
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
