//! The routes on the cost graph: where they start and end ([`ends`]), the least-cost path
//! searches ([`search`], with rows costed [`ahead`] of them and the edges already used in an
//! [`edge_set`]) and the A* bounds of KarstNSim's phreatic legs ([`spring_distance`], [`cohesion_bound`]).

pub(crate) mod ahead;
pub(crate) mod cohesion_bound;
pub(crate) mod edge_set;
pub(crate) mod ends;
pub(crate) mod search;
pub(crate) mod spring_distance;
