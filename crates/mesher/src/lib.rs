//! Stage 7: polygonizing the signed-distance model into watertight triangle meshes.
//!
//! Three solids are meshed (see `docs/mesher.md`): the carved terrain (rock, with its caves),
//! the cave alone (the karst volume under the ground) and the water in the conduits. Each
//! field is sampled on a lattice over the domain plus one cell on every side. A top-down octree
//! over bricks of [`BRICK`]³ cells skips every box the field's Lipschitz bound proves
//! empty of surface; the remaining bricks are polygonized in parallel by marching cubes with
//! one ambiguity rule for every face (`cubes.rs`), so that neighbouring cells agree and the
//! surface is closed and 2-manifold; vertices sit on lattice edges, each made once by the brick
//! that owns its edge and numbered in a fixed brick order, so the output does not depend on the
//! number of threads. Rock islands and sealed air pockets are then removed ([`clean`], Cui
//! et al. 2011 §3.2–3.3).
//! [`build`] is the entry, [`MesherStage`] the stage. Output: `mesh.bin` ([`Mesh`] of three
//! [`TriMesh`], `payload.rs`); the export stage writes them as glb, OBJ, PLY, VTK or TSurf.

mod build;
mod cell;
mod cleanup;
pub mod components;
mod cubes;
mod error;
mod estimate;
mod lattice;
mod normals;
mod octree;
mod patches;
mod payload;
mod polygonize;
mod render;
mod simplify;
mod sink;
mod spheres;
mod spill;
mod spilled;
pub mod stage;
mod terrain;
mod terrain_lattice;
mod view;
mod volume;
mod warp;
pub mod watertight;

pub use build::{anchors, build, mesh, mesh_simplified, mesh_with, meshed_field};
pub use cell::{CAVE_PERCENTILE, CAVE_REFINE, cave_cell, thickened};
pub use cleanup::{Solid, clean};
pub use error::MesherError;
pub use estimate::Work;
pub use normals::vertex_normals;
pub use octree::BRICK;
pub use patches::{Unstitched, polygonize_patched};
pub use payload::{Mesh, Removed, TriMesh};
pub use polygonize::{polygonize, polygonize_into};
pub use simplify::simplify;
pub use sink::MeshSink;
pub use stage::MesherStage;
pub use terrain::{polygonize_terrain, polygonize_terrain_into};
pub use terrain_lattice::{Patch, TerrainLattice, coarse_cell};
pub use view::MesherView;
pub use volume::{Cave, Volume, Water};
