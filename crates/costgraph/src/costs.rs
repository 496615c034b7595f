//! The edges' costs, made in memory when a search first reads a row, never stored in the
//! artifact.
//!
//! A cost is a function of the graph's two ends, the samples' positions and the scene's
//! geology ([`CostModel::edge`]). The skeleton's searches read the costs of the rows of the
//! samples they settle: a minority of them on KarstNSim's case (issue 21). Costing every edge in
//! the cost graph stage, writing the costs to `costgraph.bin` and reading them back took most of
//! the network half's time there (BENCHMARKS.md). So the artifact holds the graph, and each row is
//! costed once, in every cost set at once, the first time any search reads it
//! ([`CostGraph::row_costs`]); a search of a whole graph (the least costs to a spring) has every
//! row costed first, in parallel ([`Costing::Every`]).
//!
//! Rows are costed from whichever thread reads them first (the searches towards several springs
//! run in parallel), or by a helper costing rows ahead of a search, which never waits for one
//! ([`CostGraph::cost_row_ahead`](crate::CostGraph::cost_row_ahead)). Each row has a state,
//! empty, busy (one thread costing it) or ready, and its costs are written only while it is
//! busy, by the thread that made it so; a reader of a busy row waits for it. A row's costs are
//! the same bits whichever thread makes them, so the networks do not depend on the number of
//! threads.

use std::sync::atomic::{AtomicU8, AtomicU32, Ordering};

use rayon::prelude::*;

use crate::cost::{CostModel, NodeFields};

/// In `own_rows`: the row costs the same in every set and is held in set 0 only.
pub const SHARED_ROW: u32 = u32::MAX;

/// A row whose costs are not made yet.
const EMPTY: u8 = 0;
/// A row that one thread is costing.
const BUSY: u8 = 1;
/// A row whose costs are made.
const READY: u8 = 2;

/// Whether the rows are costed when first read or all at once.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Costing {
    /// Each row when a search first reads it.
    OnDemand,
    /// Every row now, in parallel: for searches that read the whole graph.
    Every,
}

/// The graph's rows as the costing needs them: compressed rows and the later sets' own rows
/// (see [`crate::CostGraph`]).
#[derive(Clone, Copy)]
pub(crate) struct RowsOf<'g> {
    pub offsets: &'g [u32],
    pub targets: &'g [u32],
    pub own_rows: &'g [u32],
}

impl RowsOf<'_> {
    /// Which set stores `node`'s row of set `set`, and where in that set's costs: the set's own
    /// array for an own row of a later set, set 0's otherwise.
    #[inline]
    pub(crate) fn place(&self, set: usize, node: usize) -> (usize, std::ops::Range<usize>) {
        let (first, last) = (self.offsets[node] as usize, self.offsets[node + 1] as usize);
        let own = (set > 0).then(|| self.own_rows.get(node).copied()).flatten().filter(|&s| s != SHARED_ROW);
        match own {
            Some(start) => (set, start as usize..start as usize + last - first),
            None => (0, first..last),
        }
    }
}

/// What costs a row on demand.
#[derive(Clone)]
struct Maker {
    model: CostModel,
    fields: NodeFields,
}

/// The costs of every cost set, laid out as the graph's rows: set 0 one per edge, a later set
/// one per edge of its own rows.
pub struct Costs {
    /// Per set, the costs' f32 bits.
    sets: Vec<Box<[AtomicU32]>>,
    /// Per node, the state of its row ([`EMPTY`], [`BUSY`], [`READY`]).
    rows: Box<[AtomicU8]>,
    /// None when every row is made (costs given as lists).
    maker: Option<Maker>,
}

impl Costs {
    /// Costs given for every edge: `sets[s]` laid out as set `s`'s rows.
    pub(crate) fn listed(sets: Vec<Vec<f32>>, nodes: usize) -> Self {
        Costs {
            sets: sets
                .into_iter()
                .map(|s| s.into_iter().map(|c| AtomicU32::new(c.to_bits())).collect())
                .collect(),
            rows: (0..nodes).map(|_| AtomicU8::new(READY)).collect(),
            maker: None,
        }
    }

    /// Costs made from `model` over the nodes at `positions`, `edges[s]` costs in set `s`:
    /// on demand, or every row now.
    pub(crate) fn made(
        model: CostModel,
        positions: &[[f64; 3]],
        edges: &[usize],
        rows: RowsOf,
        costing: Costing,
    ) -> Self {
        let fields = model.node_fields(positions);
        let costs = Costs {
            sets: edges.iter().map(|&n| zeroed(n)).collect(),
            rows: zeroed(positions.len()),
            maker: Some(Maker { model, fields }),
        };
        match costing {
            Costing::OnDemand => costs,
            Costing::Every => costs.all_made(rows),
        }
    }

    /// Every row made, in parallel, and the model's per-node fields dropped.
    fn all_made(mut self, rows: RowsOf) -> Self {
        (0..self.rows.len()).into_par_iter().with_min_len(1024).for_each(|node| self.ensure(rows, node));
        self.maker = None;
        self
    }

    /// Whether every row is made (costs given as lists, or [`Costing::Every`]).
    pub(crate) fn every_row_made(&self) -> bool {
        self.maker.is_none()
    }

    /// The costs of set `set` at `range`, the row of `node` (made first if need be).
    #[inline]
    #[allow(unsafe_code)]
    pub(crate) fn row(&self, rows: RowsOf, node: usize, set: usize, range: std::ops::Range<usize>) -> &[f32] {
        self.ensure(rows, node);
        let cells = &self.sets[set][range];
        // SAFETY: AtomicU32 has the size and alignment of f32. The row is ready: its cells were
        // written before the Release store of READY that `ensure`'s Acquire load saw, and no
        // cell of a ready row is written again through a shared reference (only `row_mut`,
        // which holds the costs exclusively), so nothing writes them while the slice lives.
        unsafe { std::slice::from_raw_parts(cells.as_ptr().cast::<f32>(), cells.len()) }
    }

    /// [`Costs::row`], to change them.
    #[allow(unsafe_code)]
    pub(crate) fn row_mut(
        &mut self,
        rows: RowsOf,
        node: usize,
        set: usize,
        range: std::ops::Range<usize>,
    ) -> &mut [f32] {
        self.ensure(rows, node);
        let cells = &mut self.sets[set][range];
        // SAFETY: as in `row`, and the costs are borrowed exclusively.
        unsafe { std::slice::from_raw_parts_mut(cells.as_mut_ptr().cast::<f32>(), cells.len()) }
    }

    /// Makes the row of `node` unless it is ready; waits while another thread makes it.
    #[inline]
    fn ensure(&self, rows: RowsOf, node: usize) {
        if self.rows[node].load(Ordering::Acquire) != READY {
            self.make(rows, node);
        }
    }

    #[cold]
    fn make(&self, rows: RowsOf, node: usize) {
        let state = &self.rows[node];
        loop {
            match state.compare_exchange(EMPTY, BUSY, Ordering::Acquire, Ordering::Acquire) {
                Ok(_) => break,
                Err(READY) => return,
                Err(_) => std::thread::yield_now(),
            }
        }
        self.make_held(rows, node);
    }

    /// Makes the row of `node` if nobody has begun it, without waiting: for a thread that costs
    /// rows ahead of a search ([`crate::CostGraph::cost_row_ahead`]). True when this call made it.
    pub(crate) fn make_ahead(&self, rows: RowsOf, node: usize) -> bool {
        let state = &self.rows[node];
        let free = state.load(Ordering::Relaxed) == EMPTY
            && state.compare_exchange(EMPTY, BUSY, Ordering::Acquire, Ordering::Relaxed).is_ok();
        if free {
            self.make_held(rows, node);
        }
        free
    }

    /// Costs the row of `node`, which this thread holds busy, and marks it ready.
    fn make_held(&self, rows: RowsOf, node: usize) {
        let state = &self.rows[node];
        // Back to empty if costing panics, so that a waiting thread costs the row itself
        // (and meets the same panic) instead of waiting forever.
        let busy = Busy(state);
        let maker = self.maker.as_ref().expect("a graph whose rows are not all costed keeps its cost model");
        SCRATCH.with_borrow_mut(|scratch| self.write_row(maker, rows, node, scratch));
        std::mem::forget(busy);
        state.store(READY, Ordering::Release);
    }

    /// Costs the row of `node` in every set (the thread holds it busy); a row a later set shares
    /// with set 0 is written once, in set 0.
    fn write_row(&self, maker: &Maker, rows: RowsOf, node: usize, scratch: &mut Scratch) {
        let first = rows.offsets[node] as usize;
        let targets = &rows.targets[first..rows.offsets[node + 1] as usize];
        let sets = self.sets.len();
        // Where each set stores this row: None for a later set that shares set 0's.
        scratch.places.clear();
        scratch.places.extend((0..sets).map(|set| {
            let (stored, range) = rows.place(set, node);
            (stored == set).then_some(range.start)
        }));
        scratch.costs.resize(sets, 0.0);
        for (column, &target) in targets.iter().enumerate() {
            maker.model.edge_costs(
                &maker.fields,
                (node, target as usize),
                &mut scratch.cuts,
                &mut scratch.costs,
            );
            for ((set, &cost), place) in scratch.costs.iter().enumerate().zip(&scratch.places) {
                let Some(start) = place else { continue };
                // The cost graph stage checked that every cost of the model fits ([`crate::build`]).
                let bits = cost as f32;
                debug_assert!(bits.is_finite() && bits > 0.0, "edge {node} → {target}: cost {cost}");
                self.sets[set][start + column].store(bits.to_bits(), Ordering::Relaxed);
            }
        }
    }

    /// The costs of every set as lists (costs given as lists: every row is made).
    pub(crate) fn into_lists(self) -> Vec<Vec<f32>> {
        let plain =
            |s: Box<[AtomicU32]>| s.into_vec().into_iter().map(|c| f32::from_bits(c.into_inner())).collect();
        self.sets.into_iter().map(plain).collect()
    }

    /// Bytes the costs take once every row is made (4 per stored cost).
    pub(crate) fn bytes(&self) -> usize {
        self.sets.iter().map(|s| s.len() * 4).sum()
    }
}

/// A thread's scratch space for costing rows (reused from row to row).
#[derive(Default)]
struct Scratch {
    /// Breakpoints of the edge being integrated.
    cuts: Vec<f64>,
    /// The edge's cost in every set.
    costs: Vec<f64>,
    /// Where each set stores the row (None: in set 0).
    places: Vec<Option<usize>>,
}

thread_local! {
    /// Each thread's scratch space for costing rows.
    static SCRATCH: std::cell::RefCell<Scratch> = std::cell::RefCell::new(Scratch::default());
}

/// Puts a row back to empty when dropped (only while unwinding: it is forgotten otherwise).
struct Busy<'a>(&'a AtomicU8);

impl Drop for Busy<'_> {
    fn drop(&mut self) {
        self.0.store(EMPTY, Ordering::Release);
    }
}

/// `n` atomics at zero, from zeroed memory: pages no row touches are never faulted in.
#[allow(unsafe_code)]
fn zeroed<T: Zeroable>(n: usize) -> Box<[T]> {
    let plain: Box<[T::Plain]> = vec![T::Plain::default(); n].into_boxed_slice();
    // SAFETY: T is an atomic of the same size and alignment as T::Plain, and zero is a valid
    // value of both (the trait's contract).
    unsafe { Box::from_raw(Box::into_raw(plain) as *mut [T]) }
}

/// An atomic integer whose plain integer has its layout, zero a valid value of both.
///
/// # Safety
/// `Self` and `Self::Plain` must have the same size and alignment.
#[allow(unsafe_code)]
unsafe trait Zeroable {
    type Plain: Default + Clone;
}

// SAFETY: the standard library documents both atomics as having their integer's layout.
#[allow(unsafe_code)]
unsafe impl Zeroable for AtomicU32 {
    type Plain = u32;
}
// SAFETY: as above.
#[allow(unsafe_code)]
unsafe impl Zeroable for AtomicU8 {
    type Plain = u8;
}

impl Clone for Costs {
    fn clone(&self) -> Self {
        let copy32 = |s: &[AtomicU32]| s.iter().map(|c| AtomicU32::new(c.load(Ordering::Relaxed))).collect();
        Costs {
            sets: self.sets.iter().map(|s| copy32(s)).collect(),
            // A row busy in another thread is copied as empty: the copy costs it again.
            rows: self
                .rows
                .iter()
                .map(|r| AtomicU8::new(if r.load(Ordering::Acquire) == READY { READY } else { EMPTY }))
                .collect(),
            maker: self.maker.clone(),
        }
    }
}

impl PartialEq for Costs {
    /// The same rows made, with the same costs (the model is not compared: costs of equal
    /// graphs made under one scene are equal).
    fn eq(&self, other: &Self) -> bool {
        let bits = |s: &[AtomicU32]| s.iter().map(|c| c.load(Ordering::Relaxed)).collect::<Vec<_>>();
        let states = |r: &[AtomicU8]| r.iter().map(|c| c.load(Ordering::Acquire)).collect::<Vec<_>>();
        states(&self.rows) == states(&other.rows)
            && self.sets.len() == other.sets.len()
            && self.sets.iter().zip(&other.sets).all(|(a, b)| bits(a) == bits(b))
    }
}

impl std::fmt::Debug for Costs {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let made = self.rows.iter().filter(|r| r.load(Ordering::Relaxed) == READY).count();
        f.debug_struct("Costs")
            .field("sets", &self.sets.len())
            .field("rows made", &made)
            .field("rows", &self.rows.len())
            .finish()
    }
}
