//! Stage 4: the flow of water through the conduit network.
//!
//! This first version derives flows from the routes of the skeleton: every sink feeds its
//! weight (recharge) along its route to its spring, so the flow of a conduit is the sum of the
//! weights of the sinks whose routes pass through it, signed by direction. Flow is conserved at
//! every node by construction; conduits no route uses are dry. Output: `hydro.json` ([`Hydro`]).

pub mod flow;
pub mod stage;

pub use flow::{ConduitFlow, Hydro, Outlet};
