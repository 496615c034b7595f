//! Rock added back into the void: speleothems and breakdown blocks, each an exact signed
//! distance (so 1-Lipschitz), and the union of them the field subtracts from the karst:
//! cave′ = max(cave, −min(S, [`REACH`])) with S = min over the pieces. The clamp at REACH keeps
//! the bound (a min of 1-Lipschitz functions) and lets [`RockField`] look only at the pieces
//! whose boxes come within REACH of a point, found in a uniform grid; it only lowers the
//! magnitude of the cave's value deeper than REACH inside a room, which stays a distance bound.

use glam::{DQuat, DVec3};
use serde::{Deserialize, Serialize};

use karst_artifact::Invalid;
use karst_artifact::check::{self, MAX_COORDINATE, ensure};

use crate::key_map::KeyMap;
use crate::tree::sweep::to_dvec;

/// How far the grid looks for pieces, metres (the clamp of S).
pub const REACH: f64 = 4.0;
/// Edge of the grid's cells, metres.
const CELL: f64 = 4.0;

/// What a piece of rock is, for statistics and tests.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum PieceKind {
    Stalactite,
    Stalagmite,
    Column,
    Flowstone,
    Block,
    /// A flat fill of sediment on a low-gradient passage's floor.
    Sediment,
}

impl PieceKind {
    pub const ALL: [PieceKind; 5] = [
        PieceKind::Stalactite,
        PieceKind::Stalagmite,
        PieceKind::Column,
        PieceKind::Flowstone,
        PieceKind::Block,
    ];

    pub fn name(self) -> &'static str {
        match self {
            PieceKind::Stalactite => "stalactite",
            PieceKind::Stalagmite => "stalagmite",
            PieceKind::Column => "column",
            PieceKind::Flowstone => "flowstone",
            PieceKind::Block => "block",
            PieceKind::Sediment => "sediment",
        }
    }
}

/// The shape of a piece.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub enum Shape {
    /// The convex hull of the ball of radius `ra` at `a` and the ball of radius `rb` at `b` (a
    /// cone with rounded ends); neither ball contains the other.
    Cone { a: [f32; 3], ra: f32, b: [f32; 3], rb: f32 },
    /// A box of half sizes `half` rotated by the unit quaternion `rotation` (x, y, z, w) about
    /// `centre`, its edges rounded by `round`.
    Block { centre: [f32; 3], half: [f32; 3], rotation: [f32; 4], round: f32 },
}

/// A piece of rock in the cave.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Piece {
    pub kind: PieceKind,
    pub shape: Shape,
}

impl Piece {
    /// Its signed distance, negative inside: exact.
    pub fn distance(&self, p: DVec3) -> f64 {
        match self.shape {
            Shape::Cone { a, ra, b, rb } => round_cone(p, to_dvec(a), ra as f64, to_dvec(b), rb as f64),
            Shape::Block { centre, half, rotation, round } => {
                let q = DQuat::from_array(rotation.map(|c| c as f64)).normalize();
                rounded_box(q.inverse() * (p - to_dvec(centre)), to_dvec(half), round as f64)
            }
        }
    }

    /// A point of the piece: a cone's first ball centre (a stalactite's root in the roof, a
    /// stalagmite's on the floor), a block's centre.
    pub fn centre(&self) -> DVec3 {
        match self.shape {
            Shape::Cone { a, .. } => to_dvec(a),
            Shape::Block { centre, .. } => to_dvec(centre),
        }
    }

    /// An axis-aligned box containing it.
    pub fn bounds(&self) -> (DVec3, DVec3) {
        match self.shape {
            Shape::Cone { a, ra, b, rb } => {
                let (a, b) = (to_dvec(a), to_dvec(b));
                let (ra, rb) = (DVec3::splat(ra as f64), DVec3::splat(rb as f64));
                ((a - ra).min(b - rb), (a + ra).max(b + rb))
            }
            Shape::Block { centre, half, rotation, round } => {
                // The rotated box's extent along each axis: Σ_j |R_ij| h_j, plus the rounding.
                let m = glam::DMat3::from_quat(DQuat::from_array(rotation.map(|c| c as f64)).normalize());
                let h = to_dvec(half);
                let abs = glam::DMat3::from_cols(m.x_axis.abs(), m.y_axis.abs(), m.z_axis.abs());
                let r = abs * h + DVec3::splat(round as f64 + 1e-4);
                (to_dvec(centre) - r, to_dvec(centre) + r)
            }
        }
    }

    pub fn validate(&self, at: &dyn Fn() -> String) -> Result<(), Invalid> {
        match self.shape {
            Shape::Cone { a, ra, b, rb } => {
                check::position_f32(|| format!("{}.a", at()), &a)?;
                check::position_f32(|| format!("{}.b", at()), &b)?;
                check::positive(|| format!("{}.ra", at()), ra as f64, MAX_COORDINATE)?;
                check::positive(|| format!("{}.rb", at()), rb as f64, MAX_COORDINATE)?;
                let length = to_dvec(a).distance(to_dvec(b));
                ensure(length > (ra as f64 - rb as f64).abs(), at, || {
                    format!("one ball contains the other ({length} m apart, radii {ra} and {rb})")
                })
            }
            Shape::Block { centre, half, rotation, round } => {
                check::position_f32(|| format!("{}.centre", at()), &centre)?;
                for h in half {
                    check::positive(|| format!("{}.half", at()), h as f64, MAX_COORDINATE)?;
                }
                check::within(|| format!("{}.round", at()), round as f64, 0.0, MAX_COORDINATE)?;
                let norm = rotation.iter().map(|c| (*c as f64).powi(2)).sum::<f64>().sqrt();
                check::within(|| format!("{}.rotation", at()), norm, 1.0 - 1e-4, 1.0 + 1e-4)
            }
        }
    }
}

/// The exact signed distance to the convex hull of the balls (a, ra) and (b, rb), neither
/// containing the other. In the plane of the axis and p, with y along the axis from a and x
/// the distance from it, the hull's side is the line n·(x, y) = ra with n = (c, s),
/// s = (ra − rb)/L, c = √(1 − s²) (tangent to both circles); along the side's direction
/// t = (−s, c), points before its tangent point on a's circle are nearest that circle, points
/// past its tangent point on b's nearest b's circle, the others nearest the side.
pub fn round_cone(p: DVec3, a: DVec3, ra: f64, b: DVec3, rb: f64) -> f64 {
    let axis = b - a;
    let length = axis.length();
    let u = axis / length;
    let ap = p - a;
    let y = ap.dot(u);
    let x = (ap - u * y).length();
    let s = (ra - rb) / length;
    let c = (1.0 - s * s).max(0.0).sqrt();
    let k = -s * x + c * y;
    if k < 0.0 {
        ap.length() - ra
    } else if k > length * c {
        p.distance(b) - rb
    } else {
        c * x + s * y - ra
    }
}

/// The exact signed distance to the box of half sizes `half` about the origin, rounded by
/// `round` (the box grown by `round` in every direction).
pub fn rounded_box(q: DVec3, half: DVec3, round: f64) -> f64 {
    let d = q.abs() - half;
    d.max(DVec3::ZERO).length() + d.max_element().min(0.0) - round
}

/// The pieces in a sparse uniform grid: each cell that some piece's box comes within
/// [`REACH`] of lists those pieces. Only such cells are stored (a hash of their keys), so the
/// grid's memory follows the pieces, not the extent of the cave they are scattered over (a
/// dense grid over a 6 km scene's speleothems was gigabytes).
#[derive(Debug, Clone, Default)]
pub struct RockField {
    pieces: Vec<Piece>,
    /// Each piece's box ([`Piece::bounds`]), computed once.
    boxes: Vec<(DVec3, DVec3)>,
    origin: DVec3,
    dims: [usize; 3],
    /// Per listed cell (by its key), the range of its pieces in `items`.
    cells: KeyMap<(u32, u32)>,
    items: Vec<u32>,
}

impl RockField {
    pub fn new(pieces: &[Piece]) -> Self {
        if pieces.is_empty() {
            return RockField::default();
        }
        let boxes: Vec<(DVec3, DVec3)> = pieces.iter().map(Piece::bounds).collect();
        let lo = boxes.iter().fold(DVec3::INFINITY, |m, b| m.min(b.0 - REACH));
        let hi = boxes.iter().fold(DVec3::NEG_INFINITY, |m, b| m.max(b.1 + REACH));
        let dims = ((hi - lo) / CELL).ceil().max(DVec3::ONE).to_array().map(|d| d as usize);
        let index = |v: f64, o: f64, n: usize| (((v - o) / CELL).floor().max(0.0) as usize).min(n - 1);
        // (cell key, piece), sorted by cell then piece: each cell's list in piece order.
        let mut listed: Vec<(u64, u32)> = Vec::new();
        for (k, (a, b)) in boxes.iter().map(|&(a, b)| (a - REACH, b + REACH)).enumerate() {
            let from = [0, 1, 2].map(|i| index(a[i], lo[i], dims[i]));
            let to = [0, 1, 2].map(|i| index(b[i], lo[i], dims[i]));
            for z in from[2]..=to[2] {
                for y in from[1]..=to[1] {
                    for x in from[0]..=to[0] {
                        listed.push((key(dims, [x, y, z]), k as u32));
                    }
                }
            }
        }
        listed.sort_unstable();
        let mut cells = KeyMap::default();
        let mut start = 0;
        for run in listed.chunk_by(|a, b| a.0 == b.0) {
            cells.insert(run[0].0, (start as u32, (start + run.len()) as u32));
            start += run.len();
        }
        let items = listed.iter().map(|&(_, k)| k).collect();
        RockField { pieces: pieces.to_vec(), boxes, origin: lo, dims, cells, items }
    }

    pub fn is_empty(&self) -> bool {
        self.pieces.is_empty()
    }

    /// min(REACH, the signed distance to the nearest piece): 1-Lipschitz.
    pub fn value(&self, p: DVec3) -> f64 {
        self.value_below(p, REACH)
    }

    /// min(`limit`, the signed distance to the nearest piece) for `limit` ≤ [`REACH`]: a piece
    /// whose box is at least `limit` away is not evaluated.
    fn value_below(&self, p: DVec3, limit: f64) -> f64 {
        let mut best = limit;
        if self.pieces.is_empty() {
            return best;
        }
        let rel = (p - self.origin) / CELL;
        if rel.min_element() < 0.0 {
            return best;
        }
        let [x, y, z] = rel.to_array().map(|v| v as usize);
        if x >= self.dims[0] || y >= self.dims[1] || z >= self.dims[2] {
            return best;
        }
        let Some(&(start, end)) = self.cells.get(&key(self.dims, [x, y, z])) else { return best };
        for &k in &self.items[start as usize..end as usize] {
            let (lo, hi) = self.boxes[k as usize];
            if crate::field::primitive::signed_box_distance(lo, hi, p) < best {
                best = best.min(self.pieces[k as usize].distance(p));
            }
        }
        best
    }

    /// The cave with the pieces taken out of it: max(cave, −value). Only pieces nearer than
    /// −cave can change it (a piece at S ≥ −cave gives −S ≤ cave), so the search stops there:
    /// with v = min(L, S) and L = min(REACH, −cave), max(cave, −v) is the same number, and a
    /// point in the rock (cave ≥ 0) looks only at the pieces whose boxes hold it.
    pub fn carve(&self, cave: f64, p: DVec3) -> f64 {
        if self.pieces.is_empty() { cave } else { cave.max(-self.value_below(p, REACH.min(-cave))) }
    }

    pub fn memory(&self) -> usize {
        self.pieces.len() * (std::mem::size_of::<Piece>() + std::mem::size_of::<(DVec3, DVec3)>())
            + self.cells.capacity() * (std::mem::size_of::<(u64, (u32, u32))>() + 1)
            + self.items.len() * 4
    }
}

/// A grid cell's key: its index in the dense grid of `dims` cells.
fn key(dims: [usize; 3], [x, y, z]: [usize; 3]) -> u64 {
    ((z as u64 * dims[1] as u64) + y as u64) * dims[0] as u64 + x as u64
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::testing::{Pairs, assert_lipschitz};

    fn cone(a: [f32; 3], ra: f32, b: [f32; 3], rb: f32) -> Piece {
        Piece { kind: PieceKind::Stalactite, shape: Shape::Cone { a, ra, b, rb } }
    }

    /// The hull of two balls is the union of the balls interpolated between them: outside,
    /// its distance is the least distance to them (sampled finely), and p is inside when one
    /// holds it.
    fn brute_cone(p: DVec3, a: DVec3, ra: f64, b: DVec3, rb: f64) -> f64 {
        let n = 4000;
        (0..=n)
            .map(|i| {
                let t = i as f64 / n as f64;
                p.distance(a.lerp(b, t)) - (ra + (rb - ra) * t)
            })
            .fold(f64::INFINITY, f64::min)
    }

    #[test]
    fn round_cones_and_blocks_are_one_lipschitz_and_signed() {
        let a = [0.0, 0.0, 3.0];
        let b = [0.2, 0.1, 0.5];
        let c = cone(a, 0.4, b, 0.05);
        for (p, _) in Pairs::new(3, 4.0, 1.0).around(DVec3::new(0.0, 0.0, 2.0)).take(5000) {
            let d = c.distance(p);
            let brute = brute_cone(p, to_dvec(a), 0.4, to_dvec(b), 0.05);
            if brute > 0.0 {
                assert!((d - brute).abs() < 1e-3, "{p}: {d} vs {brute}");
            } else if brute < -1e-3 {
                assert!(d < 0.0, "{p}: {d} vs {brute}");
            }
        }
        assert_lipschitz(
            |p| c.distance(p),
            Pairs::new(4, 4.0, 1.0).around(DVec3::new(0.0, 0.0, 2.0)),
            20_000,
        );
        let block = Piece {
            kind: PieceKind::Block,
            shape: Shape::Block {
                centre: [1.0, 2.0, 0.5],
                half: [1.0, 0.5, 0.3],
                rotation: DQuat::from_rotation_z(0.7)
                    .mul_quat(DQuat::from_rotation_x(0.3))
                    .as_quat()
                    .to_array(),
                round: 0.1,
            },
        };
        assert_lipschitz(|p| block.distance(p), Pairs::new(5, 4.0, 1.0), 20_000);
        assert!(block.distance(DVec3::new(1.0, 2.0, 0.5)) < -0.3);
    }

    #[test]
    fn a_round_cone_is_exact_on_its_axis_and_beside_it() {
        // Vertical cone from (0,0,0) radius 1 to (0,0,4) radius 0.5.
        let (a, b) = (DVec3::ZERO, DVec3::new(0.0, 0.0, 4.0));
        assert!((round_cone(DVec3::new(0.0, 0.0, -2.0), a, 1.0, b, 0.5) - 1.0).abs() < 1e-12);
        assert!((round_cone(DVec3::new(0.0, 0.0, 5.0), a, 1.0, b, 0.5) - 0.5).abs() < 1e-12);
        // Beside the middle: the side line's distance, less than the horizontal gap.
        let d = round_cone(DVec3::new(3.0, 0.0, 2.0), a, 1.0, b, 0.5);
        let s: f64 = 0.5 / 4.0;
        let expected = (1.0 - s * s).sqrt() * 3.0 + s * 2.0 - 1.0;
        assert!((d - expected).abs() < 1e-12 && d < 3.0 - 0.75);
    }

    #[test]
    fn the_grid_gives_the_clamped_minimum_over_every_piece() {
        let pieces: Vec<Piece> = (0..40)
            .map(|i| {
                let x = (i % 8) as f32 * 3.0;
                let y = (i / 8) as f32 * 2.5;
                cone([x, y, 5.0], 0.3, [x + 0.1, y, 5.0 - 1.0 - (i % 3) as f32], 0.05)
            })
            .collect();
        let field = RockField::new(&pieces);
        for (p, _) in Pairs::new(9, 20.0, 1.0).around(DVec3::new(10.0, 5.0, 4.0)).take(20_000) {
            let brute = pieces.iter().map(|q| q.distance(p)).fold(REACH, f64::min);
            assert_eq!(field.value(p), brute, "{p}");
            // The carve's search stops at −cave and still gives max(cave, −min(REACH, S)).
            for cave in [-6.0, -1.0, -0.2, 0.0, 0.3, 2.0, 9.0] {
                assert_eq!(field.carve(cave, p).to_bits(), cave.max(-brute).to_bits(), "{p} {cave}");
            }
        }
        assert_lipschitz(
            |p| field.carve(p.z - 6.0, p),
            Pairs::new(2, 20.0, 1.0).around(DVec3::new(10.0, 5.0, 4.0)),
            20_000,
        );
    }
}
