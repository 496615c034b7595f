//! A tortuous conduit's union of overlapping spheres `(x, y, z, r)` (a `SphereGroup` of the
//! model), indexed by a grid ([`Spheres`]) to find which spheres hold a point, from which the
//! union's wall area ([`Spheres::union_area`], the mesher's work estimate) and its axis
//! ([`Spheres::axis`], the passage's size for the automatic cave cell) are read.
//!
//! The sdf stage fills each station's section with spheres (the largest at the section's
//! deepest point, smaller ones out to its corners), so the spheres' count and their radii say
//! little about the passage until it is known which lie inside which.

use karst_sdf::KeyMap;
use rayon::prelude::*;

/// A group of spheres and a grid of cells as wide as their mean diameter, each sphere listed
/// in every cell its bounding box meets: a list of (cell key, sphere) sorted by key, and each
/// key's range of that list in a hash table. A key packs the cell's three indices,
/// [`KEY_BITS`] bits each, wrapped: cells 2^[`KEY_BITS`] cells apart share a key, and the
/// distance test of [`Spheres::holding`] drops the spheres of the other cells.
pub struct Spheres<'a> {
    spheres: &'a [[f32; 4]],
    cell: f64,
    grid: Vec<(u64, u32)>,
    cells: KeyMap<(usize, usize)>,
}

/// Bits of each cell index in a grid key.
const KEY_BITS: u32 = 21;

/// Directions at which each sphere's surface is probed by [`Spheres::union_area`].
const PROBES: usize = 24;

impl<'a> Spheres<'a> {
    /// The grid of `spheres` (empty without spheres or with a non-positive mean radius).
    pub fn of(spheres: &'a [[f32; 4]]) -> Spheres<'a> {
        let mean = spheres.iter().map(|s| s[3] as f64).sum::<f64>() / spheres.len().max(1) as f64;
        let mut out = Spheres { spheres, cell: 2.0 * mean, grid: Vec::new(), cells: KeyMap::default() };
        if spheres.is_empty() || mean.is_nan() || mean <= 0.0 {
            return out;
        }
        for (i, s) in spheres.iter().enumerate() {
            let (c, r) = ([s[0], s[1], s[2]].map(f64::from), s[3] as f64);
            let (lo, hi) = (out.key(c.map(|v| v - r)), out.key(c.map(|v| v + r)));
            for x in lo[0]..=hi[0] {
                for y in lo[1]..=hi[1] {
                    for z in lo[2]..=hi[2] {
                        out.grid.push((Self::packed([x, y, z]), i as u32));
                    }
                }
            }
        }
        out.grid.par_sort_unstable();
        let mut start = 0;
        for run in out.grid.chunk_by(|a, b| a.0 == b.0) {
            out.cells.insert(run[0].0, (start, start + run.len()));
            start += run.len();
        }
        out
    }

    fn key(&self, p: [f64; 3]) -> [i64; 3] {
        p.map(|c| (c / self.cell).floor() as i64)
    }

    /// The grid key of a cell.
    fn packed(k: [i64; 3]) -> u64 {
        let mask = (1u64 << KEY_BITS) - 1;
        k.iter().fold(0, |key, &c| (key << KEY_BITS) | (c as u64 & mask))
    }

    /// The entries listed under `key`.
    fn entries(&self, key: u64) -> &[(u64, u32)] {
        self.cells.get(&key).map_or(&[], |&(start, end)| &self.grid[start..end])
    }

    /// The spheres among `entries` (those of `p`'s key), other than `i`, that hold `p`
    /// strictly inside.
    fn holding<'e>(
        &'e self,
        entries: &'e [(u64, u32)],
        i: usize,
        p: [f64; 3],
    ) -> impl Iterator<Item = [f32; 4]> + 'e {
        entries.iter().filter_map(move |e| {
            let t = self.spheres[e.1 as usize];
            let d2 = (0..3).map(|c| (p[c] - t[c] as f64).powi(2)).sum::<f64>();
            (e.1 as usize != i && d2 < (t[3] as f64).powi(2)).then_some(t)
        })
    }

    /// The wall area of the union: each sphere's area times the share of [`PROBES`] points of
    /// its surface (a Fibonacci lattice) that lie inside no other sphere.
    pub fn union_area(&self) -> f64 {
        if self.grid.is_empty() {
            return 0.0;
        }
        let golden = std::f64::consts::PI * (3.0 - 5f64.sqrt());
        let directions: Vec<[f64; 3]> = (0..PROBES)
            .map(|k| {
                let z = 1.0 - (2 * k + 1) as f64 / PROBES as f64;
                let (r, phi) = ((1.0 - z * z).sqrt(), golden * k as f64);
                [r * phi.cos(), r * phi.sin(), z]
            })
            .collect();
        let exposed = |i: usize| {
            let s = self.spheres[i].map(|v| v as f64);
            // A sphere's probes mostly share a few cells: each cell's entries are searched once.
            let mut cell = (u64::MAX, &self.grid[..0]);
            let mut open = 0;
            for u in &directions {
                let p = [0, 1, 2].map(|c| s[c] + s[3] * u[c]);
                let key = Self::packed(self.key(p));
                if key != cell.0 {
                    cell = (key, self.entries(key));
                }
                open += usize::from(self.holding(cell.1, i, p).next().is_none());
            }
            2.0 * std::f64::consts::TAU * s[3] * s[3] * open as f64 / PROBES as f64
        };
        // In parallel, summed in order: the estimate does not depend on the thread count.
        let areas: Vec<f64> = (0..self.spheres.len()).into_par_iter().map(exposed).collect();
        areas.iter().sum()
    }

    /// The spheres of the union's axis: those whose centre lies inside no larger sphere. A
    /// station's largest sphere sits at its section's deepest point, its radius the passage's
    /// half-thickness there; the smaller spheres filling the section out to its walls have
    /// their centres inside it.
    pub fn axis(&self) -> impl Iterator<Item = [f32; 4]> + '_ {
        let on_axis = |i: usize| {
            let s = self.spheres[i];
            let centre = [s[0], s[1], s[2]].map(f64::from);
            let entries = self.entries(Self::packed(self.key(centre)));
            self.grid.is_empty() || !self.holding(entries, i, centre).any(|t| t[3] > s[3])
        };
        let kept: Vec<bool> = (0..self.spheres.len()).into_par_iter().map(on_axis).collect();
        self.spheres.iter().zip(kept).filter_map(|(s, k)| k.then_some(*s))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_lone_sphere_is_its_own_axis_and_area() {
        let spheres = [[1.0, 2.0, 3.0, 2.0]];
        let o = Spheres::of(&spheres);
        assert!((o.union_area() - 4.0 * std::f64::consts::PI * 4.0).abs() < 1e-9);
        assert_eq!(o.axis().collect::<Vec<_>>(), spheres.to_vec());
    }

    #[test]
    fn a_sphere_inside_another_adds_no_area_and_is_off_the_axis() {
        let spheres = [[0.0, 0.0, 0.0, 3.0], [0.5, 0.0, 0.0, 1.0], [10.0, 0.0, 0.0, 1.0]];
        let o = Spheres::of(&spheres);
        let big = 4.0 * std::f64::consts::PI * 9.0;
        let lone = 4.0 * std::f64::consts::PI;
        assert!((o.union_area() - big - lone).abs() < 1e-9);
        assert_eq!(o.axis().collect::<Vec<_>>(), vec![spheres[0], spheres[2]]);
    }

    #[test]
    fn spheres_whose_cells_share_a_key_do_not_hold_each_other() {
        // Cells 2^KEY_BITS apart (the cell is the mean diameter, 2 m) share a key.
        let far = (2.0f64 * (1u64 << KEY_BITS) as f64) as f32;
        let spheres = [[0.5, 0.5, 0.5, 1.0], [far + 0.5, 0.5, 0.5, 1.0]];
        let o = Spheres::of(&spheres);
        assert_eq!(o.grid.iter().filter(|e| e.0 == o.grid[0].0).count(), 2, "{:?}", o.grid);
        assert!((o.union_area() - 2.0 * 4.0 * std::f64::consts::PI).abs() < 1e-9);
        assert_eq!(o.axis().count(), 2);
    }

    #[test]
    fn two_equal_overlapping_spheres_lose_the_probes_inside_each_other() {
        let spheres = [[0.0, 0.0, 0.0, 1.0], [1.0, 0.0, 0.0, 1.0]];
        let o = Spheres::of(&spheres);
        let whole = 2.0 * 4.0 * std::f64::consts::PI;
        assert!(o.union_area() < whole && o.union_area() > 0.5 * whole);
        assert_eq!(o.axis().count(), 2, "equal spheres are both on the axis");
    }
}
