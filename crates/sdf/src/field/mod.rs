//! Evaluating the construction tree: the karst leaves ready to evaluate with their detail
//! noise and boxes ([`primitive`]), the bounding-volume hierarchy over them ([`bvh`]) and the
//! carved terrain's field at a point or over a box ([`carved`]).

pub(crate) mod bvh;
pub(crate) mod carved;
pub(crate) mod primitive;
