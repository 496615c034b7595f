//! Skeletonization of the SWMM model: chains of segments through plain passage nodes are
//! merged into conduits at least `export.swmm_conduit_length` long, with the summed length.
//!
//! Why: SWMM's dynamic-wave solver needs conduits long enough for its time step (the Courant
//! condition: a wave must not cross a conduit in less than a step) and junctions that hold
//! water; a survey-like chain of 3 m segments, each ending in a drop where it is steeper than
//! `swmm_max_slope`, makes it oscillate and never settle; so does a chain of 3 m conduits
//! between the storage units of a flooded pool. Hydraulic modellers keep a node where conduits
//! meet, where water enters or leaves and where its divides are, and merge the pipes in between;
//! the same is done here.
//!
//! A node stays a junction when it is a sink or a spring, when other than two segments meet
//! there, when the two segments do not carry the same water the same way, or when it is a sill
//! of its chain (its floor rises [`SILL`] above the lowest floor before it and falls that much
//! after it). Between two such nodes, a chain of total length T is cut into max(1, ⌊T / L⌋)
//! runs of about equal length; each run becomes one conduit from the floor at its first node to the floor at its
//! last, with the summed length, the mean full area of its segments (weighted by length; the
//! water volume of the run is kept) in the shape of its longest segment, and the nodes it passes
//! through as map vertices.

use super::section::Section;

/// A conduit of the model before the nodes' inverts are known.
#[derive(Debug, Clone, PartialEq)]
pub struct Reach {
    /// 1-based ids of its segments, along the reach.
    pub segments: Vec<u32>,
    /// Network nodes at its ends, along the water (any order when dry).
    pub ends: [u32; 2],
    /// Network nodes it passes through, along the reach.
    pub through: Vec<u32>,
    /// Elevations of its floor at its ends, metres.
    pub floors: [f64; 2],
    pub length: f64,
    pub section: Section,
    /// hydro's discharge, m³/s (0 when dry).
    pub discharge: f64,
}

impl Reach {
    fn reversed(mut self) -> Reach {
        self.ends.reverse();
        self.floors.reverse();
        self.segments.reverse();
        self.through.reverse();
        self
    }
}

/// Merges the chains of `reaches` through nodes not marked `keep`, into conduits at least
/// `min_length` long where the chain is.
pub fn merge(reaches: Vec<Reach>, keep: &[bool], min_length: f64) -> Vec<Reach> {
    let mut at: Vec<Vec<usize>> = vec![Vec::new(); keep.len()];
    for (i, r) in reaches.iter().enumerate() {
        for &n in &r.ends {
            at[n as usize].push(i);
        }
    }
    let passes = |n: u32| {
        let list = &at[n as usize];
        if keep[n as usize] || list.len() != 2 || list[0] == list[1] {
            return false;
        }
        let [a, b] = [&reaches[list[0]], &reaches[list[1]]];
        let dry = a.discharge == 0.0 && b.discharge == 0.0;
        let through = (a.ends[1] == n) != (b.ends[1] == n);
        dry || (a.discharge == b.discharge && through)
    };
    let starts = |r: &Reach| !passes(r.ends[0]) || (r.discharge == 0.0 && !passes(r.ends[1]));
    let mut used = vec![false; reaches.len()];
    let mut merged = Vec::new();
    let order: Vec<usize> =
        (0..reaches.len()).filter(|&i| starts(&reaches[i])).chain(0..reaches.len()).collect();
    for first in order {
        if used[first] {
            continue;
        }
        used[first] = true;
        let mut chain = vec![oriented(&reaches[first], &passes)];
        let mut end = chain[0].ends[1];
        while passes(end) {
            let Some(&next) = at[end as usize].iter().find(|&&i| !used[i]) else { break };
            used[next] = true;
            let r = reaches[next].clone();
            let r = if r.ends[0] == end { r } else { r.reversed() };
            end = r.ends[1];
            chain.push(r);
        }
        for piece in at_sills(chain) {
            merged.extend(runs(piece, min_length));
        }
    }
    merged
}

/// A reach turned so that it starts at a node chains do not pass (a dry reach may point
/// into its chain).
fn oriented(r: &Reach, passes: &impl Fn(u32) -> bool) -> Reach {
    if passes(r.ends[0]) && !passes(r.ends[1]) && r.discharge == 0.0 {
        r.clone().reversed()
    } else {
        r.clone()
    }
}

/// Height by which a floor must rise above the lowest one before it, and fall again below it,
/// to count as a sill, metres: less is the step between the floors of two sections at a node.
const SILL: f64 = 0.1;

/// A chain cut at its sills: the nodes where its floor, having risen, falls again. A merged
/// conduit has a straight floor between its ends, so a sill inside it would be lost: in a dry
/// chain the divide between two waters, in a wet one the pool behind it. In a piece that only
/// falls then rises, every node lies below the higher end of any run around it.
fn at_sills(chain: Vec<Reach>) -> Vec<Vec<Reach>> {
    let level = |k: usize| chain[k - 1].floors[1].max(chain[k].floors[0]);
    let mut cuts = Vec::new();
    let mut lowest = chain[0].floors[0];
    let mut peak: Option<(usize, f64)> = None;
    for k in 1..=chain.len() {
        let p = if k < chain.len() { level(k) } else { chain[k - 1].floors[1] };
        match peak {
            None if p > lowest + SILL => peak = Some((k, p)),
            None => lowest = lowest.min(p),
            Some((_, top)) if p >= top => peak = Some((k, p)),
            Some((at, top)) if p < top - SILL => {
                cuts.push(at);
                (lowest, peak) = (p, None);
            }
            Some(_) => {}
        }
    }
    let mut pieces = Vec::with_capacity(cuts.len() + 1);
    let mut rest = chain;
    for &at in cuts.iter().rev() {
        pieces.push(rest.split_off(at));
    }
    pieces.push(rest);
    pieces.reverse();
    pieces
}

/// A chain cut into runs of about equal length, at least `min_length` each where the chain is.
fn runs(chain: Vec<Reach>, min_length: f64) -> Vec<Reach> {
    let total: f64 = chain.iter().map(|r| r.length).sum();
    let count = ((total / min_length).floor() as usize).clamp(1, chain.len());
    let mut runs = Vec::with_capacity(count);
    let mut run: Vec<Reach> = Vec::new();
    let mut done = 0.0;
    for r in chain {
        done += r.length;
        run.push(r);
        if done >= total * (runs.len() + 1) as f64 / count as f64 - 1e-9 {
            runs.push(join(std::mem::take(&mut run)));
        }
    }
    if !run.is_empty() {
        runs.push(join(run));
    }
    runs
}

/// One reach from consecutive ones.
fn join(run: Vec<Reach>) -> Reach {
    if run.len() == 1 {
        return run.into_iter().next().expect("one reach");
    }
    let length: f64 = run.iter().map(|r| r.length).sum();
    let volume: f64 = run.iter().map(|r| r.section.full_area() * r.length).sum();
    let longest = run.iter().max_by(|a, b| a.length.total_cmp(&b.length)).expect("a run has reaches");
    let (first, last) = (&run[0], &run[run.len() - 1]);
    let mut through = Vec::new();
    for (k, r) in run.iter().enumerate() {
        through.extend(&r.through);
        if k + 1 < run.len() {
            through.push(r.ends[1]);
        }
    }
    Reach {
        segments: run.iter().flat_map(|r| r.segments.iter().copied()).collect(),
        ends: [first.ends[0], last.ends[1]],
        through,
        floors: [first.floors[0], last.floors[1]],
        length,
        section: longest.section.with_full_area(volume / length).rounded(),
        discharge: first.discharge,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn reach(id: u32, ends: [u32; 2], discharge: f64) -> Reach {
        Reach {
            segments: vec![id],
            ends,
            through: Vec::new(),
            floors: [10.0 - ends[0] as f64, 10.0 - ends[1] as f64],
            length: 3.0,
            section: Section::circle(2.0),
            discharge,
        }
    }

    #[test]
    fn a_chain_of_short_segments_becomes_conduits_of_the_asked_length() {
        // 0 → 1 → … → 6 (six 3 m segments), only the ends kept
        let reaches: Vec<Reach> = (0..6).map(|i| reach(i + 1, [i, i + 1], 0.5)).collect();
        let keep: Vec<bool> = (0..7).map(|n| n == 0 || n == 6).collect();
        let merged = merge(reaches, &keep, 9.0);
        assert_eq!(merged.len(), 2, "18 m in runs of at least 9 m");
        assert_eq!(merged[0].segments, [1, 2, 3]);
        assert_eq!(merged[0].ends, [0, 3]);
        assert_eq!(merged[0].through, [1, 2]);
        assert_eq!(merged[0].floors, [10.0, 7.0]);
        assert_eq!(merged[0].length, 9.0);
        assert_eq!(merged[1].ends, [3, 6]);
        assert!((merged[1].section.full_area() - Section::circle(2.0).full_area()).abs() < 1e-3);
    }

    #[test]
    fn junctions_splits_and_kept_nodes_stay() {
        // 0 → 1 → 2 with a branch 1 → 3, and 2 → 4 through a kept node
        let reaches =
            vec![reach(1, [0, 1], 1.0), reach(2, [1, 2], 0.5), reach(3, [1, 3], 0.5), reach(4, [2, 4], 0.5)];
        let keep = vec![false, false, true, false, false];
        let merged = merge(reaches.clone(), &keep, 1.0);
        assert_eq!(merged, reaches, "node 1 is a junction, node 2 is kept");
    }

    #[test]
    fn dry_chains_merge_whatever_their_segments_direction() {
        // dry 0 - 1 - 2 with segments pointing 1 → 0 and 1 → 2
        let reaches = vec![reach(1, [1, 0], 0.0), reach(2, [1, 2], 0.0)];
        let merged = merge(reaches, &[false; 3], 100.0);
        assert_eq!(merged.len(), 1);
        assert_eq!(merged[0].segments, [1, 2]);
        assert_eq!(merged[0].ends, [0, 2]);
        assert_eq!(merged[0].through, [1]);
    }

    #[test]
    fn a_sill_inside_a_chain_stays_a_node() {
        // dry 0 → 1 → 2 → 3 → 4 with its floor falling, rising to a sill at node 2, falling
        let floors = [10.0, 9.0, 11.0, 10.0, 8.0];
        let reaches: Vec<Reach> = (0..4)
            .map(|i| Reach {
                floors: [floors[i], floors[i + 1]],
                ..reach(i as u32 + 1, [i as u32, i as u32 + 1], 0.0)
            })
            .collect();
        let merged = merge(reaches, &[false; 5], 100.0);
        let ends: Vec<[u32; 2]> = merged.iter().map(|r| r.ends).collect();
        assert_eq!(ends, [[0, 2], [2, 4]], "the sill at node 2 divides the chain");
        assert_eq!(merged[0].floors, [10.0, 11.0]);
    }

    #[test]
    fn water_changing_at_a_node_keeps_it() {
        // 0 → 1 carries 1, 1 → 2 carries 0.5 (the rest leaves elsewhere): not one conduit
        let reaches = vec![reach(1, [0, 1], 1.0), reach(2, [1, 2], 0.5)];
        assert_eq!(merge(reaches.clone(), &[false; 3], 100.0), reaches);
    }
}
