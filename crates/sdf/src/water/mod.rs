//! The water of the model: the water level inside each conduit segment, from the hydro stage
//! ([`conduits`]), and the terrain adapted to its surface water, from the streams stage:
//! riverbeds, plunge basins, pools and falling sheets ([`surface`]).

pub(crate) mod conduits;
pub(crate) mod surface;
