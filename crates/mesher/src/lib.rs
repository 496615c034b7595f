//! Stage 6: polygonizing the signed-distance model into watertight triangle meshes.
//!
//! Two solids are meshed (see `docs/mesher.md`): the carved terrain (rock, with its caves) and
//! the cave alone (the karst volume under the ground). Each field is sampled on a lattice of
//! `mesher.cell_size` over the domain plus one cell on every side. A top-down octree over
//! bricks of [`octree::BRICK`]³ cells skips every box the field's Lipschitz bound proves empty
//! of surface; the remaining bricks are polygonized in parallel by marching tetrahedra over the
//! Kuhn (Freudenthal) triangulation of each cell. That triangulation is shared by neighbouring
//! cells, so there is no ambiguous face and the surface is closed and 2-manifold; vertices sit
//! on lattice edges and are welded by edge, in a fixed brick order, so the output does not
//! depend on the number of threads. Rock islands and sealed air pockets are then removed
//! ([`cleanup`], Cui et al. 2011 §3.2–3.3).
//! Output: `mesh.bin` ([`Mesh`]), `mesh.obj` (the carved terrain) and `export/`
//! (OBJ, binary PLY and .glb of both surfaces).

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
