//! From routes to the network: its nodes ([`nodes`]), the paths merged and cut into conduits
//! ([`assemble`]), each segment's tunnel type ([`classify`]) and the conduits' shape
//! ([`shape`]).

pub(crate) mod assemble;
pub(crate) mod classify;
pub(crate) mod nodes;
pub(crate) mod shape;
