//! The carved terrain's lattice: at the ground's own resolution away from the caves and the
//! streams, in fine patches at `mesher.cell_size` where they cut the rock.
//!
//! A heightfield of 30 m pixels holds no detail finer than 30 m, so a lattice of 2 m cells
//! over it spends 225 times the triangles of its pixels on nothing but bilinear facets. The
//! terrain lattice is therefore *rectilinear*: along each axis its planes are those of the
//! uniform lattice of `mesher.cell_size` (the *fine* cell), kept every `k`-th one (the
//! *coarse* cell, k fine cells: the raster's pixel, or for an analytic terrain a cell derived
//! from the extent, [`coarse_cell`]). Where a karst leaf or a surface-water piece comes near
//! the ground ([`CarvedTerrain::carves`]: openings, shafts, riverbeds, pools) the cuts are
//! clustered into [`Patch`]es, boxes of the lattice meshed on lattices of their own, fine in x
//! and y, and stitched to the coarse ground ([`crate::patches`]). A rectilinear lattice has the
//! topology of a regular one, so marching cubes on it are as closed, manifold and oriented as
//! on the regular lattice ([`crate::warp`] runs the polygonizer on it unchanged). Cuts no patch
//! can hold (near the walls or the floor) are *fine windows* of the lattice instead: every
//! plane of the fine lattice in their ranges, whole slabs across the domain.

use glam::{DVec2, DVec3};

use karst_sdf::{CarvedTerrain, SdfModel, TerrainField};

use crate::lattice::Lattice;

/// An analytic terrain (plane, noise) has no pixel: its coarse cell is the horizontal extent
/// divided by this many cells (2 m on a 2 km domain), so that the terrain's triangles do not
/// grow with the extent.
pub const ANALYTIC_CELLS: f64 = 1024.0;

/// The coarse cell of the carved terrain for a fine cell `cell`: the raster's pixel for a
/// heightfield, the extent over [`ANALYTIC_CELLS`] for an analytic terrain; never below `cell`.
pub fn coarse_cell(model: &SdfModel, cell: f64) -> f64 {
    let coarse = match &model.terrain {
        TerrainField::Grid(grid) => grid.cell_size,
        _ => {
            let size = model.domain.size();
            size.x.max(size.y) / ANALYTIC_CELLS
        }
    };
    coarse.max(cell)
}

/// The planes of the terrain lattice along each axis, world coordinates, increasing: the first
/// and the last are those of the uniform lattice of the fine cell ([`Lattice::around`]).
#[derive(Debug, Clone, PartialEq)]
pub struct TerrainLattice {
    pub planes: [Vec<f64>; 3],
    /// The fine cell, metres.
    pub fine: f64,
    /// Fine cells per coarse cell.
    pub ratio: u64,
    /// The fine patches: boxes of this lattice meshed on their own lattices of the fine cell
    /// ([`crate::patches`]); the cuts that no patch can hold (near the domain's walls or
    /// floor) are fine windows of this lattice instead.
    pub patches: Vec<Patch>,
}

/// A fine patch of the terrain lattice: a box of its planes around a cluster of cuts, meshed on
/// a lattice of its own (every fine plane in x and y; in z the terrain lattice's planes and the
/// fine windows of its cuts) where the caves and streams act only inside [`Patch::carved`].
#[derive(Debug, Clone, PartialEq)]
pub struct Patch {
    /// The box, as indices of the terrain lattice's planes along each axis (lo < hi).
    pub lo: [usize; 3],
    pub hi: [usize; 3],
    /// The patch's own lattice (no patches of its own); its first and last planes are the
    /// box's.
    pub lattice: TerrainLattice,
    /// The box inside which the caves and the streams carve, a fine cell in from the patch's
    /// faces: on the faces the field has the plain ground's sign.
    pub carved: (DVec3, DVec3),
}

impl TerrainLattice {
    /// The terrain lattice of `field` at fine cell `cell`; None when the coarse cell is less
    /// than two fine ones: the carved terrain is then meshed on the uniform lattice.
    pub fn of(field: &CarvedTerrain, cell: f64) -> Option<TerrainLattice> {
        Self::planned(field, cell, true)
    }

    /// [`TerrainLattice::of`] with every cut a fine window of whole slabs, no patch: the
    /// lattice the mesher falls back on if a patch's rim cannot be stitched.
    pub fn slabs(field: &CarvedTerrain, cell: f64) -> Option<TerrainLattice> {
        Self::planned(field, cell, false)
    }

    fn planned(field: &CarvedTerrain, cell: f64, patched: bool) -> Option<TerrainLattice> {
        let model = field.model();
        let ratio = (coarse_cell(model, cell) / cell).floor();
        if ratio < 2.0 {
            return None;
        }
        let ratio = ratio as u64;
        let fine = Lattice::around(model.domain.min(), model.domain.max(), cell);
        let cells = fine.dims.map(|d| d - 1);
        let margin = margin(field, cell);
        let all = cuts(field, &fine, ratio, margin);
        let (clusters, loose) = if patched { clusters(field, &fine, ratio, all) } else { (Vec::new(), all) };
        let mut windows = cells.map(|n| vec![false; n as usize]);
        mark_windows(&fine, margin, &loose, &mut windows);
        let kept: [Vec<u64>; 3] =
            [0, 1, 2].map(|a| (0..=cells[a]).filter(|&i| keeps(i, cells[a], ratio, &windows[a])).collect());
        let at = |a: usize, i: u64| fine.origin[a] + i as f64 * cell;
        let planes_of = |kept: &[Vec<u64>; 3]| [0, 1, 2].map(|a| kept[a].iter().map(|&i| at(a, i)).collect());
        let patches = clusters
            .into_iter()
            .map(|c| {
                let index = |a: usize, i: u64| kept[a].binary_search(&i).unwrap_or_else(|at| at);
                let mut own = [Vec::new(), Vec::new(), vec![false; cells[2] as usize]];
                mark_windows(&fine, margin, &c.cuts, &mut own);
                let z: Vec<u64> = (c.lo[2]..=c.hi[2])
                    .filter(|&i| kept[2].binary_search(&i).is_ok() || window_plane(i, &own[2]))
                    .collect();
                let own = [(c.lo[0]..=c.hi[0]).collect(), (c.lo[1]..=c.hi[1]).collect(), z];
                let corner = |i: [u64; 3]| DVec3::new(at(0, i[0]), at(1, i[1]), at(2, i[2]));
                Patch {
                    lo: [0, 1, 2].map(|a| index(a, c.lo[a])),
                    hi: [0, 1, 2].map(|a| index(a, c.hi[a])),
                    lattice: TerrainLattice {
                        planes: planes_of(&own),
                        fine: cell,
                        ratio,
                        patches: Vec::new(),
                    },
                    carved: (corner(c.lo) + cell, corner(c.hi) - cell),
                }
            })
            .collect();
        Some(TerrainLattice { planes: planes_of(&kept), fine: cell, ratio, patches })
    }

    /// Cells along each axis.
    pub fn cells(&self) -> [usize; 3] {
        [0, 1, 2].map(|a| self.planes[a].len() - 1)
    }

    /// The world point of lattice-space point `u` (plane i of an axis at u = i, affine between
    /// two planes).
    pub fn to_world(&self, u: DVec3) -> DVec3 {
        let axis = |a: usize, u: f64| {
            let planes = &self.planes[a];
            let i = (u.floor().max(0.0) as usize).min(planes.len() - 2);
            planes[i] + (u - i as f64) * (planes[i + 1] - planes[i])
        };
        DVec3::new(axis(0, u.x), axis(1, u.y), axis(2, u.z))
    }

    /// The widest cell along any axis, metres.
    pub fn widest(&self) -> f64 {
        self.planes.iter().flat_map(|p| p.windows(2).map(|w| w[1] - w[0])).fold(0.0, f64::max)
    }
}

/// Whether plane `i` bounds a cell of `window`.
fn window_plane(i: u64, window: &[bool]) -> bool {
    let fine_cell = |c: u64| window.get(c as usize).copied().unwrap_or(false);
    fine_cell(i) || (i > 0 && fine_cell(i - 1))
}

/// Whether plane `i` of `n` fine cells is kept: the lattice's first three and last three, every
/// `ratio`-th, and both planes of a fine window's cell. The domain's walls lie on or next to
/// the second and the second to last, where the field is 0 (air), so the top of a wall is the
/// highest z plane under the ground, joined to the ground at the next plane inwards: a fine
/// cell away, not a coarse one (a chamfer of a coarse cell's height along every wall).
fn keeps(i: u64, n: u64, ratio: u64, window: &[bool]) -> bool {
    i <= 2 || i + 2 >= n || i.is_multiple_of(ratio) || window_plane(i, window)
}

/// A fine cell of the ground that a cut reaches: its x and y cells, and the range of its
/// ground's heights.
struct Cut {
    cell: [u64; 2],
    ground: (f64, f64),
}

/// Marks, along each axis, the fine cells of the windows around `cuts`: the cut's x and y
/// cells and one more on either side, and its ground's heights, all grown by `margin` (an
/// empty window along an axis is left alone).
fn mark_windows(fine: &Lattice, margin: f64, cuts: &[Cut], windows: &mut [Vec<bool>; 3]) {
    let grow = (margin / fine.cell).ceil() as u64;
    for cut in cuts {
        for (window, at) in windows.iter_mut().zip(cut.cell) {
            let n = window.len() as u64;
            if n > 0 {
                let (from, to) = (at.saturating_sub(grow), (at + grow + 1).min(n));
                window[from as usize..to as usize].fill(true);
            }
        }
        let n = windows[2].len() as f64;
        let z = |h: f64| ((h - fine.origin.z) / fine.cell).floor().clamp(0.0, n) as usize;
        let (from, to) = (z(cut.ground.0 - margin), (z(cut.ground.1 + margin) + 1).min(windows[2].len()));
        windows[2][from..to].fill(true);
    }
}

/// A cluster of cuts and the box of fine planes (indices of the uniform fine lattice) that
/// holds them as a patch.
struct Cluster {
    lo: [u64; 3],
    hi: [u64; 3],
    cuts: Vec<Cut>,
}

/// Groups `cuts` into clusters whose boxes become patches, and returns the cuts no patch can
/// hold. A cut's x and y cells grown by the margin are marked on the grid of coarse columns,
/// with one more column all round (so that a patch's faces stand at least a coarse cell from
/// every cut, on the plain ground); the marked columns' connected pieces are boxed, and boxes
/// closer than a column apart merged until none are. In z a box runs from the lowest coarse
/// plane over the floor (the caves under the cuts are meshed down to it) to the coarse plane
/// over its ground's highest point (plus the margin and a fine cell). A box must lie strictly inside the domain's walls and above its floor, where the
/// plain ground is rock under its surface and air over it on every vertical line of the
/// box's faces; the cuts of the other boxes are returned.
fn clusters(field: &CarvedTerrain, fine: &Lattice, ratio: u64, cuts: Vec<Cut>) -> (Vec<Cluster>, Vec<Cut>) {
    let model = field.model();
    let cell = fine.cell;
    let margin = margin(field, cell);
    let grow = (margin / cell).ceil() as u64;
    let cells = fine.dims.map(|d| d - 1);
    let columns = [0, 1].map(|a| cells[a].div_ceil(ratio) as usize);
    let span = |cut: &Cut, a: usize| {
        let from = (cut.cell[a].saturating_sub(grow) / ratio).saturating_sub(1) as usize;
        let to = (((cut.cell[a] + grow).min(cells[a] - 1) / ratio) as usize + 1).min(columns[a] - 1);
        (from, to)
    };
    let mut marked = vec![false; columns[0] * columns[1]];
    for cut in &cuts {
        let ((x0, x1), (y0, y1)) = (span(cut, 0), span(cut, 1));
        for y in y0..=y1 {
            marked[y * columns[0] + x0..=y * columns[0] + x1].fill(true);
        }
    }
    // Boxes of the connected pieces, [x0, y0, x1, y1] in columns, inclusive.
    let mut boxes: Vec<[usize; 4]> = Vec::new();
    let mut seen = vec![false; marked.len()];
    for start in 0..marked.len() {
        if !marked[start] || seen[start] {
            continue;
        }
        let (x, y) = (start % columns[0], start / columns[0]);
        let mut b = [x, y, x, y];
        let mut stack = vec![start];
        seen[start] = true;
        while let Some(c) = stack.pop() {
            let (x, y) = (c % columns[0], c / columns[0]);
            b = [b[0].min(x), b[1].min(y), b[2].max(x), b[3].max(y)];
            let mut visit = |n: usize| {
                if marked[n] && !seen[n] {
                    seen[n] = true;
                    stack.push(n);
                }
            };
            if x > 0 {
                visit(c - 1);
            }
            if x + 1 < columns[0] {
                visit(c + 1);
            }
            if y > 0 {
                visit(c - columns[0]);
            }
            if y + 1 < columns[1] {
                visit(c + columns[0]);
            }
        }
        boxes.push(b);
    }
    let near = |a: &[usize; 4], b: &[usize; 4]| {
        a[0] <= b[2] + 1 && b[0] <= a[2] + 1 && a[1] <= b[3] + 1 && b[1] <= a[3] + 1
    };
    'merge: loop {
        for i in 0..boxes.len() {
            for j in i + 1..boxes.len() {
                if near(&boxes[i], &boxes[j]) {
                    let b = boxes.swap_remove(j);
                    let a = &mut boxes[i];
                    *a = [a[0].min(b[0]), a[1].min(b[1]), a[2].max(b[2]), a[3].max(b[3])];
                    continue 'merge;
                }
            }
        }
        break;
    }
    boxes.sort_unstable_by_key(|b| [b[1], b[0]]);
    let mut members: Vec<Vec<Cut>> = boxes.iter().map(|_| Vec::new()).collect();
    for cut in cuts {
        let [x, y] = cut.cell.map(|i| (i / ratio) as usize);
        let owner = boxes.iter().position(|b| b[0] <= x && x <= b[2] && b[1] <= y && y <= b[3]);
        members[owner.expect("every cut's column is in a box")].push(cut);
    }
    let (terrain, domain) = (&model.terrain, &model.domain);
    let slack = terrain.lipschitz() * cell * std::f64::consts::FRAC_1_SQRT_2;
    let at = |a: usize, i: u64| fine.origin[a] + i as f64 * cell;
    let (mut clusters, mut loose) = (Vec::new(), Vec::new());
    for (b, cuts) in boxes.into_iter().zip(members) {
        let lo = [b[0] as u64 * ratio, b[1] as u64 * ratio];
        let hi = [(b[2] as u64 + 1) * ratio, (b[3] as u64 + 1) * ratio];
        let inside =
            (0..2).all(|a| hi[a] <= cells[a] && at(a, lo[a]) > domain.min[a] && at(a, hi[a]) < domain.max[a]);
        let ground = (lo[1]..=hi[1].min(cells[1]))
            .flat_map(|j| (lo[0]..=hi[0].min(cells[0])).map(move |i| (i, j)))
            .map(|(i, j)| terrain.height(at(0, i), at(1, j)))
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), h| (a.min(h), b.max(h)));
        let reach = margin + slack + cell;
        let (bottom, top) = (ground.0 - reach, ground.1 + reach);
        let k = |z: f64| (z - fine.origin.z) / cell;
        // The lowest coarse plane over the floor: the shafts are meshed down to it.
        let z0 = ((k(domain.min[2]).floor().max(0.0) as u64) / ratio + 1) * ratio;
        let z1 = ((k(top).ceil().max(0.0) as u64).div_ceil(ratio) * ratio).min(cells[2]);
        let holds = inside && at(2, z0) > domain.min[2] && at(2, z0) <= bottom && at(2, z1) >= top;
        if holds {
            clusters.push(Cluster { lo: [lo[0], lo[1], z0], hi: [hi[0], hi[1], z1], cuts });
        } else {
            loose.extend(cuts);
        }
    }
    (clusters, loose)
}

/// How near the ground a cave or a stream cuts it: a fine cell and the blend of the cave
/// entrances.
fn margin(field: &CarvedTerrain, cell: f64) -> f64 {
    cell + field.model().blend.max(0.0)
}

/// The fine cells of the ground within `margin` of a cave or a surface-water piece, in
/// (y, x) order. Each coarse column (`ratio` fine cells square) is tested as a whole first
/// ([`CarvedTerrain::may_carve`] over its ground's heights), then its fine cells one by one
/// ([`CarvedTerrain::carves`]). A fine cell's ground lies within the heights at its corners
/// less and plus the ground's Lipschitz bound times half a cell diagonal.
fn cuts(field: &CarvedTerrain, fine: &Lattice, ratio: u64, margin: f64) -> Vec<Cut> {
    use rayon::prelude::*;
    let model = field.model();
    let (terrain, cell) = (&model.terrain, fine.cell);
    let slack = terrain.lipschitz() * cell * std::f64::consts::FRAC_1_SQRT_2;
    let cells = [0, 1].map(|a| fine.dims[a] - 1);
    let (floor, ceiling) = (model.domain.min[2], model.domain.max[2]);
    let corner = |i: u64, j: u64| {
        let (x, y) = (fine.origin.x + i as f64 * cell, fine.origin.y + j as f64 * cell);
        (DVec2::new(x, y), terrain.height(x, y))
    };
    // The whole column first, from its four corners alone: its ground lies within their heights
    // less and plus the Lipschitz bound times half its diagonal, so a column no cut can reach
    // costs four heights, not (ratio + 1)² (a fine cell far below the raster's).
    let column_may_be_cut = |i0: u64, j0: u64, i1: u64, j1: u64| {
        let corners = [corner(i0, j0), corner(i1, j0), corner(i0, j1), corner(i1, j1)];
        let (lo, hi) =
            corners.iter().fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), &(_, v)| (a.min(v), b.max(v)));
        let reach = terrain.lipschitz() * cell * 0.5 * ((i1 - i0) as f64).hypot((j1 - j0) as f64);
        let (bottom, top) = ((lo - reach).max(floor), (hi + reach).min(ceiling));
        bottom > top || field.may_carve(corners[0].0.extend(bottom), corners[3].0.extend(top), margin)
    };
    let column = |&[i0, j0]: &[u64; 2]| -> Vec<Cut> {
        let (i1, j1) = ((i0 + ratio).min(cells[0]), (j0 + ratio).min(cells[1]));
        if !column_may_be_cut(i0, j0, i1, j1) {
            return Vec::new();
        }
        let heights: Vec<f64> = (j0..=j1).flat_map(|j| (i0..=i1).map(move |i| corner(i, j).1)).collect();
        let row = (i1 - i0 + 1) as usize;
        let ground = |i: u64, j: u64| {
            let at = |di: u64, dj: u64| heights[(j - j0 + dj) as usize * row + (i - i0 + di) as usize];
            let h = [at(0, 0), at(1, 0), at(0, 1), at(1, 1)];
            let (lo, hi) =
                h.iter().fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), &v| (a.min(v), b.max(v)));
            ((lo - slack).max(floor), (hi + slack).min(ceiling))
        };
        let boxed = |i: u64, j: u64, di: u64, dj: u64, (bottom, top): (f64, f64)| {
            let lo = corner(i, j).0;
            let hi = lo + DVec2::new(di as f64, dj as f64) * cell;
            (lo.extend(bottom), hi.extend(top))
        };
        let subcells: Vec<([u64; 2], (f64, f64))> = (j0..j1)
            .flat_map(|j| (i0..i1).map(move |i| [i, j]))
            .map(|[i, j]| ([i, j], ground(i, j)))
            .collect();
        let whole = subcells
            .iter()
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), &(_, (lo, hi))| (a.min(lo), b.max(hi)));
        if subcells.is_empty() || whole.0 > whole.1 {
            return Vec::new();
        }
        let (lo, hi) = boxed(i0, j0, i1 - i0, j1 - j0, whole);
        if !field.may_carve(lo, hi, margin) {
            return Vec::new();
        }
        subcells
            .into_iter()
            .filter(|&([i, j], ground)| {
                ground.0 <= ground.1 && {
                    let (lo, hi) = boxed(i, j, 1, 1, ground);
                    field.carves(lo, hi, margin)
                }
            })
            .map(|(cell, ground)| Cut { cell, ground })
            .collect()
    };
    let columns: Vec<[u64; 2]> = (0..cells[1])
        .step_by(ratio as usize)
        .flat_map(|j| (0..cells[0]).step_by(ratio as usize).map(move |i| [i, j]))
        .collect();
    columns.par_iter().flat_map_iter(column).collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn keeps_every_ratio_th_plane_and_the_windows() {
        let mut window = vec![false; 20];
        window[7] = true;
        let kept: Vec<u64> = (0..=20).filter(|&i| keeps(i, 20, 5, &window)).collect();
        assert_eq!(kept, vec![0, 1, 2, 5, 7, 8, 10, 15, 18, 19, 20]);
    }

    #[test]
    fn an_analytic_terrain_takes_its_coarse_cell_from_the_extent() {
        let model = SdfModel::new(
            karst_geology::Domain { min: [0.0; 3], max: [4096.0, 1000.0, 50.0] },
            TerrainField::Plane { elevation: 25.0, origin: [0.0, 0.0], gradient: [0.0, 0.0] },
        );
        assert_eq!(coarse_cell(&model, 1.0), 4.0);
        assert_eq!(coarse_cell(&model, 8.0), 8.0);
    }
}
