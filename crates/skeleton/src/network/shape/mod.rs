//! The shape of the conduits: the planes of weakness they follow ([`planes`]), their tortuosity
//! ([`tortuosity`]) and meanders ([`meander`]), their radii ([`radii`]) and passage profiles
//! ([`passages`]).

pub(crate) mod meander;
pub(crate) mod passages;
pub(crate) mod planes;
pub(crate) mod radii;
pub(crate) mod tortuosity;
