//! The one binary glTF 2.0 writer of karstgen, shared by the export's `karst.glb`
//! (crates/export) and the web viewer's compressed chunks (crates/view).
//!
//! - [`Gltf`] assembles a document: buffer views (plain, streamed into the binary chunk, or
//!   compressed with EXT_meshopt_compression over an empty fallback buffer), accessors,
//!   materials, meshes and nodes;
//! - [`Glb`] is the finished file, laid out from its counts before a byte of its buffer is
//!   written, so a large file streams from the caller's arrays to the disk;
//! - [`quantize`] holds KHR_mesh_quantization's integer positions and normals;
//! - [`simplify`] reduces a triangle mesh to a triangle count with meshoptimizer's edge
//!   collapse, for files meant for viewers rather than archives.
//!
//! Axes: glTF is Y-up, karstgen Z-up; [`y_up`] and [`Z_UP_TO_Y_UP`] are the one −90° turn about
//! x, (x, y, z) → (x, z, −y), a rotation, so windings and orientations are kept.
//!
//! The JSON is built with `serde_json` maps, whose keys are sorted: the bytes of a document
//! depend only on its content, never on the order the writer set its fields in.

mod builder;
mod container;
pub mod quantize;
pub mod simplify;

pub use builder::Gltf;
pub use container::Fill;
pub use container::Glb;

/// Accessor component types.
pub const BYTE: u32 = 5120;
pub const UNSIGNED_SHORT: u32 = 5123;
pub const UNSIGNED_INT: u32 = 5125;
pub const FLOAT: u32 = 5126;
/// Buffer view targets.
pub const ARRAY_BUFFER: u32 = 34962;
pub const ELEMENT_ARRAY_BUFFER: u32 = 34963;
/// Primitive modes.
pub const LINES: u32 = 1;
pub const TRIANGLES: u32 = 4;

/// The extension that compresses buffer views with meshoptimizer's codecs.
pub const MESHOPT: &str = "EXT_meshopt_compression";
/// The extension that allows integer positions and normals.
pub const QUANTIZATION: &str = "KHR_mesh_quantization";

/// The unit quaternion of −90° about x: Z-up to glTF's Y-up, for a node's `rotation`.
pub const Z_UP_TO_Y_UP: [f64; 4] =
    [-std::f64::consts::FRAC_1_SQRT_2, 0.0, 0.0, std::f64::consts::FRAC_1_SQRT_2];

/// A Z-up vector turned Y-up: (x, y, z) → (x, z, −y).
pub fn y_up([x, y, z]: [f32; 3]) -> [f32; 3] {
    [x, z, -y]
}

/// Why a file cannot be made.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum GltfError {
    /// The file would pass glTF's 4 GiB (its header's length is 32 bits).
    TooLarge { bytes: usize },
    /// A meshoptimizer codec refused its input.
    Codec(String),
}

impl std::fmt::Display for GltfError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            GltfError::TooLarge { bytes } => write!(f, "the file would be {bytes} bytes, over glTF's 4 GiB"),
            GltfError::Codec(detail) => write!(f, "meshopt codec: {detail}"),
        }
    }
}

impl std::error::Error for GltfError {}
