//! The cost graph artifact: directed edges in compressed sparse rows, the cost sets they are
//! routed on, the distributions of the costs.
//!
//! Targets are u32: 4 bytes per edge plus 4 per node for the row offsets. The costs are not
//! stored: they are a function of the graph, the samples and the scene's geology, made in
//! memory for the rows the searches read (`costs.rs`, [`CostGraph::cost_from`]); the artifact
//! records the scene sections they come from (`made_under`), so that they are never made under
//! another geology than the graph's.
//!
//! KarstNSim's water-table term differs per water table, so the karstnsim2024 model has one
//! cost set per water table named by a spring; paris2021 has one set. Set 0 is the default set
//! and holds every edge's cost. The later sets differ from it only near the water tables: above
//! every water table an edge's term depends on its direction alone, far below every one it is
//! the same constant, so most rows cost the same in every set (most of them on the regional
//! scene). A later set therefore holds only the rows that may differ (`own_rows`), and the
//! others are read from set 0: a fraction of the memory of full sets (BENCHMARKS.md).

use std::sync::OnceLock;

use rayon::prelude::*;
use serde::{Deserialize, Serialize};

use karst_artifact::check::{self, ensure};
use karst_artifact::{DecodeError, Invalid, Payload, PayloadReader, StageId};
use karst_scene::SceneView;

use crate::cost::CostModel;
use crate::costs::{Costing, Costs, RowsOf, SHARED_ROW};
use crate::stats::Summary;
use crate::view::CostgraphView;

/// Directed graph over the samples: the out-edges of sample `i` are
/// `targets[offsets[i]..offsets[i + 1]]`, with their costs in every cost set at
/// [`CostGraph::row_costs`] once the graph is costed ([`CostGraph::cost_from`]).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct CostGraph {
    #[serde(with = "karst_artifact::bulk")]
    pub offsets: Vec<u32>,
    #[serde(with = "karst_artifact::bulk")]
    pub targets: Vec<u32>,
    /// With several cost sets, one entry per node: where its row starts in the costs of every
    /// set after the first, or [`SHARED_ROW`] when the row costs the same in every set (set 0
    /// holds it). Own rows follow each other in node order. Empty with one cost set.
    #[serde(with = "karst_artifact::bulk")]
    pub own_rows: Vec<u32>,
    /// At least one cost set; set 0 is the default.
    pub cost_sets: Vec<CostSet>,
    /// The hash of the scene sections the costs come from (the cost graph stage's: geology,
    /// key points, connectivity, costgraph, forced links); empty for graphs made from lists.
    pub made_under: String,
    /// Distributions of the edge lengths and of every cost term, for `inspect`.
    pub summary: Summary,
    /// The costs, in memory only: made from the scene's model ([`CostGraph::cost_from`]) or
    /// given as lists.
    #[serde(skip)]
    costs: OnceLock<Costs>,
}

/// One cost set: the costs of the edges under one water table (or the only set of a model
/// without one).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct CostSet {
    /// The water table whose C_WT these costs use; None for paris2021.
    pub water_table: Option<String>,
    /// A lower bound of every edge's cost per metre (cost / length, between distinct
    /// positions), the factor of the searches' A* heuristic: the cost model's own bound
    /// ([`CostModel::least_cost_per_metre`]), so that no stage reads every edge to find it;
    /// None when unknown (graphs made from lists).
    pub min_cost_per_metre: Option<f64>,
}

/// Why a graph cannot be costed under a scene.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum CostingError {
    #[error(
        "was made under other scene sections ({sections}) than the scene's: its costs would not be the scene's"
    )]
    OtherScene { sections: String },
    #[error("has {nodes} nodes, the samples are {samples}")]
    OtherSamples { nodes: usize, samples: usize },
}

impl Payload for CostGraph {
    const STAGE: StageId = StageId::Costgraph;
    const SCHEMA: u32 = 5;

    /// Rows that start at 0, never go back and end at the last edge; targets that are nodes;
    /// own rows (with several sets) that follow each other in node order; at least one cost
    /// set, no two of one water table; a least cost per metre, when known, finite and ≥ 0 (the
    /// A* heuristic's factor: NaN or ∞ would misdirect the searches).
    fn validate(&self) -> Result<(), Invalid> {
        ensure(self.offsets.first() == Some(&0), || "offsets".into(), || "must start with 0".into())?;
        if let Some(i) = self.offsets.windows(2).position(|w| w[1] < w[0]) {
            let (a, b) = (self.offsets[i], self.offsets[i + 1]);
            return Err(Invalid::new(
                format!("offsets[{}]", i + 1),
                format!("{b} is below offsets[{i}] = {a}"),
            ));
        }
        let last = self.offsets.last().copied().unwrap_or(0) as usize;
        check::count(|| "targets".into(), self.targets.len(), last)?;
        let nodes = self.node_count();
        // Targets are hundreds of millions of numbers on a regional scene: they are scanned on
        // every core ([`first_where`]).
        if let Some(e) = first_where(&self.targets, |&t| t as usize >= nodes) {
            check::index(|| format!("targets[{e}]"), self.targets[e] as u64, nodes)?;
        }
        ensure(!self.cost_sets.is_empty(), || "cost_sets".into(), || "is empty: no cost to route on".into())?;
        self.validate_own_rows()?;
        for (s, set) in self.cost_sets.iter().enumerate() {
            if let Some(least) = set.min_cost_per_metre {
                check::within(|| format!("cost_sets[{s}].min_cost_per_metre"), least, 0.0, f64::MAX)?;
            }
            if self.cost_sets[..s].iter().any(|o| o.water_table == set.water_table) {
                return Err(Invalid::new(
                    format!("cost_sets[{s}].water_table"),
                    format!("{:?} has two cost sets", set.water_table),
                ));
            }
        }
        Ok(())
    }

    /// Decoded as the file is read: the arrays, most of a large graph's payload, go straight
    /// into their vectors instead of being held twice.
    fn read_streamed(bytes: &mut PayloadReader) -> Option<Result<Self, DecodeError>> {
        Some(read_graph(bytes))
    }
}

/// The payload's fields in postcard's order (as serde derives them: the round trip is tested).
fn read_graph(bytes: &mut PayloadReader) -> Result<CostGraph, DecodeError> {
    let offsets = bytes.bulk()?;
    let targets = bytes.bulk()?;
    let own_rows = bytes.bulk()?;
    // Each set takes at least 2 bytes: the count is bounded by the payload's length, but sets
    // are pushed one by one rather than allocated for a count a corrupted file may inflate.
    let count = bytes.length()?;
    let mut cost_sets = Vec::new();
    for s in 0..count {
        let water_table = match option_tag(bytes, s)? {
            false => None,
            true => Some(string(bytes, &format!("cost_sets[{s}].water_table"))?),
        };
        let min_cost_per_metre = match option_tag(bytes, s)? {
            false => None,
            true => Some(f64::from_le_bytes(bytes.bytes(8)?.try_into().expect("8 bytes read"))),
        };
        cost_sets.push(CostSet { water_table, min_cost_per_metre });
    }
    let made_under = string(bytes, "made_under")?;
    Ok(CostGraph {
        offsets,
        targets,
        own_rows,
        cost_sets,
        made_under,
        summary: bytes.tail()?,
        costs: OnceLock::new(),
    })
}

/// A postcard string: its length, then its UTF-8 bytes.
fn string(bytes: &mut PayloadReader, field: &str) -> Result<String, DecodeError> {
    let n = bytes.length()?;
    String::from_utf8(bytes.bytes(n)?)
        .map_err(|e| DecodeError::Field { field: field.into(), problem: e.to_string() })
}

/// The index of the first element of `values` for which `bad` holds, scanning blocks of them
/// on every core (a parallel search element by element would test an atomic flag per element).
fn first_where<T: Sync>(values: &[T], bad: impl Fn(&T) -> bool + Sync) -> Option<usize> {
    const BLOCK: usize = 1 << 16;
    let block = values.par_chunks(BLOCK).position_first(|block| block.iter().any(&bad))?;
    let start = block * BLOCK;
    values[start..].iter().position(bad).map(|at| start + at)
}

/// Whether an option of cost set `s` holds a value (postcard: a byte 0 or 1).
fn option_tag(bytes: &mut PayloadReader, s: usize) -> Result<bool, DecodeError> {
    match bytes.byte()? {
        0 => Ok(false),
        1 => Ok(true),
        tag => Err(DecodeError::Field {
            field: format!("cost_sets[{s}]"),
            problem: format!("an option tagged {tag}"),
        }),
    }
}

impl CostGraph {
    /// Number of nodes (samples).
    pub fn node_count(&self) -> usize {
        self.offsets.len().saturating_sub(1)
    }

    /// Number of directed edges.
    pub fn edge_count(&self) -> usize {
        self.targets.len()
    }

    /// Out-edges of `node` as (target, cost) in the default cost set.
    pub fn out_edges(&self, node: usize) -> impl Iterator<Item = (usize, f32)> + '_ {
        self.out_edges_in(0, node)
    }

    /// Out-edges of `node` as (target, cost) in cost set `set`.
    pub fn out_edges_in(&self, set: usize, node: usize) -> impl Iterator<Item = (usize, f32)> + '_ {
        let range = self.offsets[node] as usize..self.offsets[node + 1] as usize;
        self.targets[range].iter().map(|&t| t as usize).zip(self.row_costs(set, node).iter().copied())
    }

    /// Costs the graph's edges under the cost model of `view` (the cost graph stage's sections,
    /// [`CostgraphView`]), the samples at `positions`: each row when first read, or every row
    /// now ([`Costing`]). Nothing changes when the graph is costed already (from lists, or by an
    /// earlier call: the view is then checked all the same). Refused when the graph was made
    /// under other scene sections, or over other samples.
    pub fn cost_from(
        &self,
        view: &CostgraphView,
        positions: &[[f64; 3]],
        costing: Costing,
    ) -> Result<(), CostingError> {
        if !self.made_under.is_empty() && self.made_under != view.sections_hash() {
            let sections: Vec<&str> = CostgraphView::SECTIONS.iter().map(|s| s.key()).collect();
            return Err(CostingError::OtherScene { sections: sections.join(", ") });
        }
        if positions.len() != self.node_count() {
            return Err(CostingError::OtherSamples { nodes: self.node_count(), samples: positions.len() });
        }
        if self.costs.get().is_none() {
            let edges = self.set_edges();
            let costs = Costs::made(CostModel::new(view), positions, &edges, self.rows_of(), costing);
            // Another thread may have costed it meanwhile, under the same scene: either will do.
            let _ = self.costs.set(costs);
        }
        Ok(())
    }

    /// Whether the graph's costs are available ([`CostGraph::cost_from`], or lists).
    pub fn is_costed(&self) -> bool {
        self.costs.get().is_some()
    }

    /// The costs of `node`'s out-edges in cost set `set`, in the order of its row (made now if
    /// no search read them before).
    ///
    /// # Panics
    /// When the graph is not costed: [`CostGraph::cost_from`] comes first.
    #[inline]
    pub fn row_costs(&self, set: usize, node: usize) -> &[f32] {
        let rows = self.rows_of();
        let (stored, range) = rows.place(set, node);
        self.costs().row(rows, node, stored, range)
    }

    /// Whether every row's costs are made already (from lists, or [`Costing::Every`]): no
    /// search will cost a row.
    pub fn every_row_costed(&self) -> bool {
        self.costs.get().is_some_and(Costs::every_row_made)
    }

    /// Costs the row of `node` in every set now, unless it is made or another thread is making
    /// it (never waits): a thread with nothing else to do costs the rows a search will read
    /// soon, so that the search finds them made. Nothing happens on a graph not costed yet.
    /// True when this call costed the row.
    pub fn cost_row_ahead(&self, node: usize) -> bool {
        self.costs.get().is_some_and(|costs| costs.make_ahead(self.rows_of(), node))
    }

    /// [`CostGraph::row_costs`], to change them (a shared row changes in every set).
    pub fn row_costs_mut(&mut self, set: usize, node: usize) -> &mut [f32] {
        let rows = RowsOf { offsets: &self.offsets, targets: &self.targets, own_rows: &self.own_rows };
        let (stored, range) = rows.place(set, node);
        self.costs.get_mut().expect(UNCOSTED).row_mut(rows, node, stored, range)
    }

    fn costs(&self) -> &Costs {
        self.costs.get().expect(UNCOSTED)
    }

    fn rows_of(&self) -> RowsOf<'_> {
        RowsOf { offsets: &self.offsets, targets: &self.targets, own_rows: &self.own_rows }
    }

    /// How many costs each set holds: every edge in set 0, the own rows' edges in later sets.
    fn set_edges(&self) -> Vec<usize> {
        let own: usize = (0..self.node_count())
            .filter(|&i| self.own_rows.get(i).is_some_and(|&start| start != SHARED_ROW))
            .map(|i| (self.offsets[i + 1] - self.offsets[i]) as usize)
            .sum();
        (0..self.cost_sets.len()).map(|s| if s == 0 { self.edge_count() } else { own }).collect()
    }

    /// Own rows empty with one set, one per node with several, each starting where the
    /// previous own row ends.
    fn validate_own_rows(&self) -> Result<(), Invalid> {
        if self.cost_sets.len() <= 1 {
            return check::count(|| "own_rows".into(), self.own_rows.len(), 0);
        }
        check::count(|| "own_rows".into(), self.own_rows.len(), self.node_count())?;
        let mut next = 0usize;
        for (i, &start) in self.own_rows.iter().enumerate() {
            if start == SHARED_ROW {
                continue;
            }
            ensure(
                start as usize == next,
                || format!("own_rows[{i}]"),
                || format!("{start}: the previous own rows end at {next}"),
            )?;
            next += (self.offsets[i + 1] - self.offsets[i]) as usize;
        }
        ensure(
            u32::try_from(next).is_ok(),
            || "own_rows".into(),
            || format!("hold {next} edges, more than 32-bit places can address"),
        )
    }

    /// The cost set to route towards a spring of water table `name`: its own set under
    /// karstnsim2024, the only set under paris2021; None when the graph has no set for it.
    pub fn cost_set_of_water_table(&self, name: &str) -> Option<usize> {
        match self.cost_sets.as_slice() {
            [only] if only.water_table.is_none() => Some(0),
            sets => sets.iter().position(|s| s.water_table.as_deref() == Some(name)),
        }
    }

    /// Bytes the graph's arrays hold in memory once every row is costed (lengths, not
    /// capacities; 4 per stored cost whether the graph is costed yet or not).
    pub fn bytes_in_memory(&self) -> usize {
        let costs = self.costs.get().map_or_else(|| self.set_edges().iter().sum::<usize>() * 4, Costs::bytes);
        (self.offsets.len() + self.targets.len() + self.own_rows.len()) * 4 + costs
    }

    /// The share of rows that some cost set holds apart (0 with one set).
    pub fn own_row_share(&self) -> f64 {
        let own = self.own_rows.iter().filter(|&&s| s != SHARED_ROW).count();
        own as f64 / self.node_count().max(1) as f64
    }

    /// A graph with one cost set from per-node out-edge lists, in node order (tests, tools).
    pub fn from_lists(lists: Vec<Vec<(u32, f32)>>) -> Self {
        let mut offsets = Vec::with_capacity(lists.len() + 1);
        let mut targets = Vec::new();
        let mut costs = Vec::new();
        offsets.push(0);
        for list in lists {
            for (t, c) in list {
                targets.push(t);
                costs.push(c);
            }
            offsets.push(targets.len() as u32);
        }
        let nodes = offsets.len() - 1;
        CostGraph {
            offsets,
            targets,
            own_rows: Vec::new(),
            cost_sets: vec![CostSet { water_table: None, min_cost_per_metre: None }],
            made_under: String::new(),
            summary: Summary::default(),
            costs: OnceLock::from(Costs::listed(vec![costs], nodes)),
        }
    }

    /// The graph with the costs of a later set appended, `own_rows` and `costs` laid out as
    /// [`CostGraph::own_rows`] says (tests, tools).
    pub fn with_listed_set(
        mut self,
        water_table: Option<String>,
        own_rows: Vec<u32>,
        costs: Vec<f32>,
    ) -> Self {
        let listed = self.costs.take().map(|c| c.into_lists()).unwrap_or_default();
        self.cost_sets.push(CostSet { water_table, min_cost_per_metre: None });
        self.own_rows = own_rows;
        let nodes = self.node_count();
        self.costs = OnceLock::from(Costs::listed(listed.into_iter().chain([costs]).collect(), nodes));
        self
    }

    /// A graph without costs: `offsets`, `targets`, `own_rows`, the sets and their summary
    /// (the cost graph stage).
    pub(crate) fn uncosted(
        (offsets, targets, own_rows): (Vec<u32>, Vec<u32>, Vec<u32>),
        cost_sets: Vec<CostSet>,
        made_under: String,
        summary: Summary,
    ) -> Self {
        CostGraph { offsets, targets, own_rows, cost_sets, made_under, summary, costs: OnceLock::new() }
    }
}

/// The message of the panic of a graph read before [`CostGraph::cost_from`].
const UNCOSTED: &str = "the cost graph is costed (CostGraph::cost_from) before its costs are read";

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn cost_sets_are_found_by_water_table() {
        let g = CostGraph::from_lists(vec![vec![(1, 1.0)], vec![(0, 2.0)]]);
        assert_eq!(g.cost_set_of_water_table("any"), Some(0));
        // Row 0 is the same in both sets, row 1 is held apart.
        let mut g = g.with_listed_set(Some("low".into()), vec![SHARED_ROW, 0], vec![4.0]);
        g.cost_sets[0].water_table = Some("high".into());
        assert_eq!(g.validate(), Ok(()));
        assert_eq!(g.cost_set_of_water_table("low"), Some(1));
        assert_eq!(g.cost_set_of_water_table("none"), None);
        assert_eq!(g.out_edges_in(1, 1).collect::<Vec<_>>(), vec![(0, 4.0)]);
        assert_eq!(g.out_edges_in(1, 0).collect::<Vec<_>>(), vec![(1, 1.0)]);
        assert_eq!(g.out_edges(1).collect::<Vec<_>>(), vec![(0, 2.0)]);
        assert_eq!(g.bytes_in_memory(), 3 * 4 + 2 * 4 + 2 * 4 + 3 * 4);
        assert_eq!(g.own_row_share(), 0.5);
        g.row_costs_mut(1, 0)[0] = 7.0;
        assert_eq!(g.row_costs(0, 0), [7.0], "a shared row changes in every set");
    }

    #[test]
    fn own_rows_must_follow_each_other_and_fit_the_later_sets() {
        let g = CostGraph::from_lists(vec![vec![(1, 1.0), (2, 1.0)], vec![(0, 2.0)], vec![(0, 3.0)]]);
        let mut g = g.with_listed_set(Some("low".into()), vec![0, SHARED_ROW, SHARED_ROW], vec![5.0, 6.0]);
        g.cost_sets[0].water_table = Some("high".into());
        let with = |own_rows: Vec<u32>| {
            let mut g = g.clone();
            g.own_rows = own_rows;
            g.validate().map_err(|e| format!("{}: {}", e.field, e.problem))
        };
        assert_eq!(with(vec![0, SHARED_ROW, SHARED_ROW]), Ok(()));
        assert_eq!(with(vec![SHARED_ROW, 0, 1]), Ok(()));
        assert!(with(vec![SHARED_ROW, 1, 0]).unwrap_err().contains("own_rows[1]"));
        assert!(with(vec![0, 2]).unwrap_err().contains("own_rows: has 2 items, expected 3"));
        assert!(with(vec![]).is_err(), "two sets need a row map");
    }

    /// `g` without its costs, as a read artifact is.
    fn uncosted(g: &CostGraph) -> CostGraph {
        let arrays = (g.offsets.clone(), g.targets.clone(), g.own_rows.clone());
        CostGraph::uncosted(arrays, g.cost_sets.clone(), g.made_under.clone(), g.summary.clone())
    }

    #[test]
    fn the_streamed_read_decodes_what_postcard_does() {
        let listed = CostGraph::from_lists(vec![vec![(1, 1.5), (2, 0.25)], vec![(0, 2.0)], vec![]]);
        let mut g = uncosted(&listed.with_listed_set(None, vec![SHARED_ROW, 0, SHARED_ROW], vec![4.0]));
        g.cost_sets[0].water_table = Some("haut-é".into());
        g.cost_sets[0].min_cost_per_metre = Some(0.125);
        g.made_under = "0a1b".into();
        g.summary.model = "karstnsim2024".into();
        let bytes = postcard::to_stdvec(&g).unwrap();
        let path = std::path::Path::new("costgraph.bin");
        let read =
            karst_artifact::decode_payload::<CostGraph>(path, karst_artifact::Encoding::Postcard, &bytes);
        assert_eq!(read.unwrap(), g);
        assert_eq!(postcard::from_bytes::<CostGraph>(&bytes).unwrap(), g);
        // Cut anywhere, or with an option tag that is not 0 or 1, it is a decoding error.
        for end in 0..bytes.len() {
            let cut = karst_artifact::decode_payload::<CostGraph>(
                path,
                karst_artifact::Encoding::Postcard,
                &bytes[..end],
            );
            assert!(matches!(cut, Err(karst_artifact::Error::Decode { .. })), "cut at {end}");
        }
    }

    #[test]
    fn a_streamed_file_keeps_the_envelope_checks() {
        use karst_artifact::{Error, Frame, Provenance, read_artifact, write_artifact};
        let dir = karst_testkit::scratch("streamed-costgraph");
        let path = dir.join("costgraph.bin");
        let graph = uncosted(&CostGraph::from_lists(
            (0..3000).map(|i| vec![((i + 1) % 3000, 1.0 + i as f32)]).collect(),
        ));
        let provenance = Provenance {
            producer: "test".into(),
            inputs: vec![],
            params: "p".into(),
            frame: Frame::default(),
        };
        write_artifact(&path, &provenance, &graph).unwrap();
        assert_eq!(read_artifact::<CostGraph>(&path).unwrap().1, graph);
        let bytes = std::fs::read(&path).unwrap();
        let with = |bytes: &[u8]| {
            std::fs::write(&path, bytes).unwrap();
            read_artifact::<CostGraph>(&path).unwrap_err()
        };
        // A flipped byte in the targets, or in the offsets' length (decoding then fails first).
        for at in [bytes.len() - 2000, bytes.iter().position(|b| *b == b'\n').unwrap() + 2] {
            let mut flipped = bytes.clone();
            flipped[at] ^= 0x40;
            assert!(matches!(with(&flipped), Error::Checksum { .. }), "byte {at}");
        }
        assert!(
            matches!(with(&bytes[..bytes.len() - 7]), Error::Length { found, .. } if found + 7 == graph_len(&bytes))
        );
        assert!(matches!(with(&[bytes.as_slice(), b"x"].concat()), Error::Length { .. }));
        std::fs::remove_dir_all(&dir).unwrap();
    }

    /// The payload length of an artifact file's bytes (after its header line).
    fn graph_len(bytes: &[u8]) -> u64 {
        (bytes.len() - bytes.iter().position(|b| *b == b'\n').unwrap() - 1) as u64
    }
}
