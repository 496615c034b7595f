//! Stage 6: polygonizing the signed-distance model into watertight triangle meshes.
//!
//! Three solids are meshed (see `docs/mesher.md`): the carved terrain (rock, with its caves),
//! the cave alone (the karst volume under the ground) and the water in the conduits. Each
//! field is sampled on a lattice over the domain plus one cell on every side. A top-down octree
//! over bricks of [`octree::BRICK`]³ cells skips every box the field's Lipschitz bound proves
//! empty of surface; the remaining bricks are polygonized in parallel by marching cubes with
//! one ambiguity rule for every face ([`cubes`]), so that neighbouring cells agree and the
//! surface is closed and 2-manifold; vertices sit on lattice edges, each made once by the brick
//! that owns its edge and numbered in a fixed brick order, so the output does not depend on the
//! number of threads. Rock islands and sealed air pockets are then removed ([`cleanup`], Cui
//! et al. 2011 §3.2–3.3).
//! Output: `mesh.bin` ([`Mesh`]), `mesh.obj` (the carved terrain) and `export/`
//! (OBJ, binary PLY and .glb of the three surfaces).

pub mod build;
pub mod cleanup;
pub mod components;
pub mod cubes;
pub mod export;
pub mod lattice;
pub mod mesh;
pub mod normals;
pub mod octree;
pub mod polygonize;
pub mod render;
pub mod simplify;
pub mod stage;
pub mod volume;
pub mod watertight;

pub use mesh::{Mesh, Surface};
