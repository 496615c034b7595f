//! The k-nearest-neighbour graph in compressed rows, built in parallel with a deterministic
//! result, and its symmetrisation and transpose.

use rayon::prelude::*;

use crate::grid::{self, Grid};

/// Nodes per parallel work item. Fixed, so that results never depend on the thread count.
pub const CHUNK: usize = 2048;

/// The nodes of chunk `c` of `n` nodes: [`CHUNK`] consecutive ones (fewer in the last).
pub fn chunk_nodes(c: usize, n: usize) -> std::ops::Range<usize> {
    c * CHUNK..((c + 1) * CHUNK).min(n)
}

/// Directed edges in compressed rows: the out-edges of node `i` are
/// `targets[offsets[i]..offsets[i + 1]]`.
#[derive(Debug, Clone, PartialEq)]
pub struct Rows {
    pub offsets: Vec<u32>,
    pub targets: Vec<u32>,
}

impl Rows {
    pub fn node_count(&self) -> usize {
        self.offsets.len() - 1
    }

    pub fn row(&self, i: usize) -> &[u32] {
        &self.targets[self.offsets[i] as usize..self.offsets[i + 1] as usize]
    }

    /// Assembles rows computed in chunks of consecutive nodes (chunk c holds the rows of
    /// [`chunk_nodes`]`(c, ..)`, as row lengths and concatenated targets).
    fn from_chunks(chunks: Vec<(Vec<u32>, Vec<u32>)>) -> Rows {
        let mut offsets = vec![0u32];
        for len in chunks.iter().flat_map(|(lengths, _)| lengths) {
            offsets.push(offsets[offsets.len() - 1] + len);
        }
        let targets = chunks.into_iter().flat_map(|(_, targets)| targets).collect();
        Rows { offsets, targets }
    }

    /// The graph with every edge reversed ([`transpose`]).
    pub fn transpose(&self) -> Rows {
        let (offsets, targets) = transpose(&self.offsets, &self.targets);
        Rows { offsets, targets }
    }

    /// Adds the reverse j → i of every edge i → j that is missing. Each row keeps its
    /// neighbours first, then the added sources in increasing order.
    pub fn symmetrised(&self) -> Rows {
        let n = self.node_count();
        let sorted: Vec<Vec<u32>> = (0..n)
            .into_par_iter()
            .map(|i| {
                let mut row = self.row(i).to_vec();
                row.sort_unstable();
                row
            })
            .collect();
        // Missing reverse edges, as (row j, source i): for each j the sources come in
        // increasing i because the transpose lists them so.
        let reverse = self.transpose();
        let chunks: Vec<(Vec<u32>, Vec<u32>)> = (0..n.div_ceil(CHUNK))
            .into_par_iter()
            .map(|c| {
                let nodes = chunk_nodes(c, n);
                let mut lengths = Vec::with_capacity(nodes.len());
                let mut list = Vec::new();
                for j in nodes {
                    let start = list.len();
                    list.extend_from_slice(self.row(j));
                    list.extend(reverse.row(j).iter().filter(|&&i| sorted[j].binary_search(&i).is_err()));
                    lengths.push((list.len() - start) as u32);
                }
                (lengths, list)
            })
            .collect();
        Rows::from_chunks(chunks)
    }
}

/// The rows `offsets`/`targets` (out-edges of node i: `targets[offsets[i]..offsets[i + 1]]`)
/// reversed: the in-edges' sources of every node, in increasing order, as rows.
pub fn transpose(offsets: &[u32], targets: &[u32]) -> (Vec<u32>, Vec<u32>) {
    let reversed = reversed_offsets(offsets, targets);
    let mut sources = vec![0u32; targets.len()];
    transpose_values(offsets, targets, &reversed, |source| move |_| source as u32, &mut sources);
    (reversed, sources)
}

/// The row offsets of the reversed rows: where the in-edges of every node start.
fn reversed_offsets(offsets: &[u32], targets: &[u32]) -> Vec<u32> {
    let n = offsets.len().saturating_sub(1);
    let counts: Vec<Vec<u32>> = node_ranges(n).par_iter().map(|&range| in_degrees(targets, range)).collect();
    let mut reversed = Vec::with_capacity(n + 1);
    reversed.push(0u32);
    for count in counts.iter().flatten() {
        reversed.push(reversed[reversed.len() - 1] + count);
    }
    reversed
}

/// Writes the value of every edge into `values` (one per edge), laid out as the reversed rows
/// whose offsets are `reversed` (from [`transpose`]): the in-edges of each node, by increasing
/// source. `row(source)` gives the values of a source's out-edges by their place in its row, so
/// that a row stored elsewhere (a cost set's costs) is looked up once per row, not per edge.
///
/// A counting sort whose writes land all over the result (a cache miss per edge): the nodes are
/// split into one range per thread, and each thread scans every edge but writes only the rows of
/// its own range. Each row's sources come in increasing order whatever the split, so the result
/// does not depend on the number of threads.
pub fn transpose_values<T: Send, R: Fn(usize) -> T>(
    offsets: &[u32],
    targets: &[u32],
    reversed: &[u32],
    row: impl Fn(usize) -> R + Sync,
    values: &mut [T],
) {
    assert_eq!(values.len(), targets.len(), "one value per edge");
    let n = offsets.len().saturating_sub(1);
    let mut rest = values;
    let mut pieces = Vec::new();
    for (lo, hi) in node_ranges(n) {
        let (piece, tail) = rest.split_at_mut((reversed[hi] - reversed[lo]) as usize);
        pieces.push(((lo, hi), piece));
        rest = tail;
    }
    pieces.into_par_iter().for_each(|((lo, hi), piece)| {
        let base = reversed[lo];
        let mut next: Vec<u32> = reversed[lo..hi].iter().map(|&o| o - base).collect();
        for (source, bounds) in offsets.windows(2).enumerate() {
            let value = row(source);
            for (place, &target) in targets[bounds[0] as usize..bounds[1] as usize].iter().enumerate() {
                let slot = (target as usize).checked_sub(lo).and_then(|at| next.get_mut(at));
                if let Some(at) = slot {
                    piece[*at as usize] = value(place);
                    *at += 1;
                }
            }
        }
    });
}

/// One range of nodes per thread, covering `0..n`.
fn node_ranges(n: usize) -> Vec<(usize, usize)> {
    let parts = rayon::current_num_threads().clamp(1, n.max(1));
    (0..parts).map(|p| (p * n / parts, (p + 1) * n / parts)).collect()
}

/// How many of `targets` are in `lo..hi`, per node of that range.
fn in_degrees(targets: &[u32], (lo, hi): (usize, usize)) -> Vec<u32> {
    let mut counts = vec![0u32; hi - lo];
    for &t in targets {
        if let Some(count) = (t as usize).checked_sub(lo).and_then(|at| counts.get_mut(at)) {
            *count += 1;
        }
    }
    counts
}

/// For every point, its `k` nearest other points, nearest first (ties by index), leaving out
/// those farther than `max_length`. Results depend on neither the number of threads nor the
/// order of the queries.
///
/// Queried in chunks of [`CHUNK`] consecutive points, each row written in place in a table of
/// `k` slots per point (then closed up when some rows are shorter): no per-chunk lists copied
/// into place afterwards, which held every target twice. Samples come in Morton order
/// (karst-sampling's storage order), so a chunk of consecutive samples is a compact region:
/// its queries share their neighbours' cells in cache, and each query's search radius, guessed
/// from the previous one, is a good guess. `done` is called after each chunk (progress).
pub fn neighbours(
    points: &[[f64; 3]],
    (k, max_length): (usize, Option<f64>),
    done: &(dyn Fn() + Sync),
) -> Rows {
    if points.len() < 2 || k == 0 {
        return Rows { offsets: vec![0; points.len() + 1], targets: Vec::new() };
    }
    let grid = Grid::new(points);
    let max2 = max_length.map(|l| l * l).unwrap_or(f64::INFINITY);
    let mut table = vec![0u32; points.len() * k];
    let mut lengths = vec![0u32; points.len()];
    table.par_chunks_mut(CHUNK * k).zip(lengths.par_chunks_mut(CHUNK)).enumerate().for_each(
        |(c, (rows, lengths))| {
            let mut row: Vec<u64> = Vec::with_capacity(4 * k);
            let mut radius = grid.initial_radius(k);
            for (at, (slots, length)) in rows.chunks_mut(k).zip(lengths.iter_mut()).enumerate() {
                grid.nearest(c * CHUNK + at, k, max2, &mut radius, &mut row);
                *length = row.len() as u32;
                for (slot, &key) in slots.iter_mut().zip(&row) {
                    *slot = grid::index(key);
                }
            }
            done();
        },
    );
    closed_up(table, &lengths, k)
}

/// The rows of `table` (`k` slots per node, the first `lengths[i]` used) as compressed rows,
/// moved down in place over the unused slots.
fn closed_up(mut table: Vec<u32>, lengths: &[u32], k: usize) -> Rows {
    let mut offsets = Vec::with_capacity(lengths.len() + 1);
    offsets.push(0u32);
    let mut end = 0usize;
    for (i, &length) in lengths.iter().enumerate() {
        let length = length as usize;
        if end != i * k {
            table.copy_within(i * k..i * k + length, end);
        }
        end += length;
        offsets.push(end as u32);
    }
    table.truncate(end);
    table.shrink_to_fit();
    Rows { offsets, targets: table }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::grid::distance2;

    fn cloud(n: usize) -> Vec<[f64; 3]> {
        let mut state = 12345u64;
        let mut next = || {
            state ^= state << 13;
            state ^= state >> 7;
            state ^= state << 17;
            (state >> 11) as f64 / (1u64 << 53) as f64 * 100.0
        };
        (0..n).map(|_| [next(), next(), next()]).collect()
    }

    #[test]
    fn matches_brute_force() {
        let points = cloud(300);
        // A loose and a tight maximum length: with the tight one most rows are short or empty,
        // and the table of k slots per node is closed up.
        for max_length in [30.0, 12.0] {
            let got = neighbours(&points, (7, Some(max_length)), &|| ());
            for i in 0..points.len() {
                let mut all: Vec<(u32, f64)> = (0..points.len())
                    .filter(|&j| j != i)
                    .map(|j| (j as u32, distance2(&points[i], &points[j]).sqrt()))
                    .collect();
                all.sort_by(|a, b| a.1.total_cmp(&b.1).then(a.0.cmp(&b.0)));
                let expected: Vec<u32> =
                    all.iter().take(7).filter(|n| n.1 <= max_length).map(|n| n.0).collect();
                assert_eq!(got.row(i), expected.as_slice(), "node {i}, max length {max_length}");
            }
        }
    }

    #[test]
    fn transpose_lists_every_source_in_order_whatever_the_threads() {
        let points = cloud(700);
        let rows = neighbours(&points, (6, None), &|| ());
        let mut expected = vec![Vec::new(); rows.node_count()];
        for i in 0..rows.node_count() {
            for &t in rows.row(i) {
                expected[t as usize].push(i as u32);
            }
        }
        for threads in [1, 2, 3, 8] {
            let pool = rayon::ThreadPoolBuilder::new().num_threads(threads).build().expect("a pool");
            let reverse = pool.install(|| rows.transpose());
            for (j, sources) in expected.iter().enumerate() {
                assert_eq!(reverse.row(j), sources.as_slice(), "row {j} with {threads} threads");
            }
        }
    }

    #[test]
    fn symmetrised_graph_has_every_reverse_edge_once() {
        let points = cloud(500);
        let rows = neighbours(&points, (5, None), &|| ());
        let sym = rows.symmetrised();
        assert!(sym.targets.len() > rows.targets.len());
        for i in 0..sym.node_count() {
            assert_eq!(&sym.row(i)[..rows.row(i).len()], rows.row(i));
            let mut row = sym.row(i).to_vec();
            row.sort_unstable();
            row.dedup();
            assert_eq!(row.len(), sym.row(i).len(), "duplicate edge out of {i}");
            for &j in sym.row(i) {
                assert!(sym.row(j as usize).contains(&(i as u32)), "{j} → {i} missing");
            }
        }
        assert_eq!(sym.symmetrised(), sym);
    }
}
