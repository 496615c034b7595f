//! Stage 6: polygonizing the signed-distance model into a watertight triangle mesh.
//!
//! The field is sampled on a lattice of `mesher.cell_size` over the domain plus one cell of
//! air on every side. A top-down octree over bricks of [`octree::BRICK`]³ cells skips every box
//! the field's Lipschitz bound proves empty of surface; the remaining bricks are polygonized in
//! parallel by marching tetrahedra over the Kuhn (Freudenthal) triangulation of each cell. That
//! triangulation is shared by neighbouring cells, so there is no ambiguous face and the surface
//! is closed and 2-manifold; vertices sit on lattice edges and are welded by edge, in a fixed
//! brick order, so the output does not depend on the number of threads.
//! Output: `mesh.bin` ([`Mesh`]) and `mesh.obj`.

pub mod lattice;
pub mod mesh;
pub mod octree;
pub mod polygonize;
pub mod stage;
pub mod tetra;

pub use mesh::Mesh;
