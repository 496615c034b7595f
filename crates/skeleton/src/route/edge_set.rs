//! A set of the cost graph's edge ids, one bit per edge: the per-edge flags of the routing
//! (the edges an earlier phase's conduits use, the edges used so far in a phase) over graphs
//! of a hundred million edges and more, where a byte per edge would cost eight times the
//! memory (BENCHMARKS.md, 2026-12-07).

/// Bits per word.
const WORD: usize = u64::BITS as usize;

/// A set of edge ids below a fixed bound, stored as a bit per id.
#[derive(Clone, Debug, Default)]
pub struct EdgeSet {
    words: Vec<u64>,
    len: usize,
}

impl EdgeSet {
    /// The empty set of the ids below `len`.
    pub fn new(len: usize) -> Self {
        EdgeSet { words: vec![0; len.div_ceil(WORD)], len }
    }

    /// Whether `edge` is in the set.
    #[inline]
    pub fn contains(&self, edge: usize) -> bool {
        debug_assert!(edge < self.len, "edge {edge} of a set of {} edges", self.len);
        self.words[edge / WORD] >> (edge % WORD) & 1 != 0
    }

    /// Adds `edge` to the set.
    #[inline]
    pub fn insert(&mut self, edge: usize) {
        assert!(edge < self.len, "edge {edge} of a set of {} edges", self.len);
        self.words[edge / WORD] |= 1 << (edge % WORD);
    }

    /// Adds every edge of `other`, a set over the same ids.
    pub fn union_with(&mut self, other: &EdgeSet) {
        assert_eq!(self.len, other.len, "sets over different edges");
        for (word, theirs) in self.words.iter_mut().zip(&other.words) {
            *word |= theirs;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn holds_exactly_the_edges_inserted() {
        // Across word boundaries and up to the last id of a partial word.
        let marked = [0, 1, 63, 64, 65, 127, 128, 199];
        let mut set = EdgeSet::new(200);
        for &e in &marked {
            set.insert(e);
        }
        set.insert(64); // again: no change
        for e in 0..200 {
            assert_eq!(set.contains(e), marked.contains(&e), "edge {e}");
        }
    }

    #[test]
    fn union_adds_the_other_sets_edges() {
        let (mut a, mut b) = (EdgeSet::new(130), EdgeSet::new(130));
        a.insert(3);
        b.insert(3);
        b.insert(129);
        a.union_with(&b);
        let members: Vec<usize> = (0..130).filter(|&e| a.contains(e)).collect();
        assert_eq!(members, vec![3, 129]);
        assert!(!b.contains(4));
    }

    #[test]
    #[should_panic(expected = "edge 10 of a set of 10 edges")]
    fn an_edge_out_of_bounds_is_refused() {
        EdgeSet::new(10).insert(10);
    }
}
