//! The input of [`crate::characterize`]: node coordinates and undirected links, plus the checks
//! that keep karstnet's silent failure modes out (spec §0).
//!
//! karstnet builds its graph from the link list only (`nx.Graph().add_edges_from`): duplicate or
//! reversed links collapse and nodes in no link are ignored — both are accepted here too. A
//! self-loop, however, silently corrupts karstnet's branches, so it is an error, as are link
//! indices out of range, non-finite coordinates and networks without links.

use thiserror::Error;

/// A network as karstnet sees it: 3D node coordinates and undirected links (0-based indices).
///
/// For a 2D network set z = 0 (karstnet does the same when it reads 2 coordinates).
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Network {
    /// Node coordinates `[x, y, z]`.
    pub nodes: Vec<[f64; 3]>,
    /// Undirected links between node indices; order and direction do not matter.
    pub links: Vec<[usize; 2]>,
}

/// Why a [`Network`] cannot be characterised.
#[derive(Debug, Clone, PartialEq, Error)]
pub enum MetricsError {
    /// The network has no link (karstnet's graph would have no node).
    #[error("the network has no link")]
    NoLinks,
    /// A link refers to a node index `>= nodes.len()`.
    #[error("link {link} refers to node {node}, but there are only {n_nodes} nodes")]
    LinkOutOfRange { link: usize, node: usize, n_nodes: usize },
    /// A link joins a node to itself (karstnet would silently corrupt its branches).
    #[error("link {link} is a self-loop on node {node}")]
    SelfLoop { link: usize, node: usize },
    /// A coordinate is NaN or infinite.
    #[error("node {node} has a non-finite coordinate {coordinates:?}")]
    NonFiniteCoordinate { node: usize, coordinates: [f64; 3] },
}

impl Network {
    /// Checks the bad-input policy of the module docs; `Ok` means [`crate::characterize`] can run.
    pub fn validate(&self) -> Result<(), MetricsError> {
        if self.links.is_empty() {
            return Err(MetricsError::NoLinks);
        }
        if let Some((node, p)) = self.nodes.iter().enumerate().find(|(_, p)| p.iter().any(|c| !c.is_finite()))
        {
            return Err(MetricsError::NonFiniteCoordinate { node, coordinates: *p });
        }
        self.links.iter().enumerate().try_for_each(|(link, &[a, b])| self.check_link(link, a, b))
    }

    fn check_link(&self, link: usize, a: usize, b: usize) -> Result<(), MetricsError> {
        let n_nodes = self.nodes.len();
        if let Some(node) = [a, b].into_iter().find(|&i| i >= n_nodes) {
            return Err(MetricsError::LinkOutOfRange { link, node, n_nodes });
        }
        if a == b {
            return Err(MetricsError::SelfLoop { link, node: a });
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn net(links: Vec<[usize; 2]>) -> Network {
        Network { nodes: vec![[0.0; 3], [1.0, 0.0, 0.0], [2.0, 0.0, 0.0]], links }
    }

    #[test]
    fn accepts_duplicates_and_unused_nodes() {
        assert_eq!(net(vec![[0, 1], [1, 0], [0, 1]]).validate(), Ok(()));
    }

    #[test]
    fn rejects_bad_input() {
        assert_eq!(net(vec![]).validate(), Err(MetricsError::NoLinks));
        assert_eq!(
            net(vec![[0, 1], [2, 3]]).validate(),
            Err(MetricsError::LinkOutOfRange { link: 1, node: 3, n_nodes: 3 })
        );
        assert_eq!(net(vec![[0, 1], [2, 2]]).validate(), Err(MetricsError::SelfLoop { link: 1, node: 2 }));
        let mut bad = net(vec![[0, 1]]);
        bad.nodes[2][1] = f64::NAN;
        assert!(matches!(bad.validate(), Err(MetricsError::NonFiniteCoordinate { node: 2, .. })));
    }
}
