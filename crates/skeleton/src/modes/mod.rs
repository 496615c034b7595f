//! The synthesis modes, chosen by `skeleton.mode`, that draw the routes of the network:
//! Paris et al. 2021's γ-skeleton of the key points ([`gamma`]) and KarstNSim's routing of every
//! sink with cohesion ([`karstnsim`]); then amplification, the loops and tributaries added to
//! either ([`amplify`]).

pub(crate) mod amplify;
pub(crate) mod gamma;
pub(crate) mod karstnsim;
#[cfg(test)]
mod tests;
