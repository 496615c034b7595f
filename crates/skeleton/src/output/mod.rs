//! What the stage writes besides `skeleton.json`: karstnet's `.dat` files ([`karstnet`]) and
//! the network picture of `karst-skeleton render` ([`render`]).

pub(crate) mod karstnet;
pub(crate) mod render;
