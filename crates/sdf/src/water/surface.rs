//! The terrain adapted to its surface water (Emilien et al. 2015 §6), from the streams stage's
//! network: pieces that carve riverbeds with their banks, plunge basins at the feet of falls
//! and the overhang behind each fall, and the water bodies of rivers, pools and falling sheets.
//!
//! Where the paper deforms a heightfield with diffused constraints, the pieces here are
//! signed-distance leaves combined with min and max, so the carved field keeps the 1-Lipschitz
//! bound (tested like the cave's leaves):
//!
//! - a **bed** (a contact segment, or a plunge basin: a bed of zero length) removes the rock
//!   above the surface b(x, y) = z_w + max(−ζ, ζ·s/w) inside the wetted half-width w and
//!   z_w + k·s beyond it (s = d − w, d the horizontal distance to the segment, z_w the water
//!   surface along it, ζ the depth, k `streams.bank_slope`): the paper's triangular section
//!   below the water, banks rising at k above it. Its value max((b − z)/√(1 + λ²), d − w_c)
//!   (λ the slope bound of b, w_c where the banks stop) is 1-Lipschitz;
//! - a **basin** (a pool controller) removes the rock above b(x, y) = z_l + max(−ζ, k·s),
//!   s the signed horizontal distance to the pool's outline (negative inside), z_l its level,
//!   ζ its depth: sides at the bank slope below the water down to a flat floor, banks at the
//!   same slope above it. s is 1-Lipschitz, so b is k-Lipschitz and the value
//!   max((b − z)/√(1 + k²), s − w_c) is 1-Lipschitz;
//! - an **alcove** (a capsule under a fall's lip, across the fall) hollows the cliff behind
//!   the falling sheet, leaving the lip as an overhang (the flipped "S" of Fig. 13);
//! - **water**: under the water surface within a bed (rivers, plunge pools), under the level
//!   of a filled hollow within its flooded cells (pools, lakes) or its outline (pool
//!   controllers), and thin oriented boxes along each fall's parabola (the falling sheet).
//!
//! The carved rock is max(rock, −carve) and the surface water max(water, −carved rock): the
//! water stays in the air and fills the beds to their surface. Spring mouths are capsules from
//! the key point to the mouth, added to the karst so that the conduit opens onto the stream.
//! Both unions are clamped like the karst's (at [`crate::tree::ops::REACH`], or farther from every
//! piece), and a grid of 2D cells lists the pieces that can matter at each point.

use glam::{DVec2, DVec3};
use serde::{Deserialize, Serialize};

use karst_scene::params::StreamsParams;
use karst_streams::{Motion, Outline, PoolKind, Streams};

use karst_artifact::Invalid;
use karst_artifact::check::{self, MAX_COORDINATE};

use crate::Capsule;
use crate::tree::ops::REACH;

/// A riverbed or a plunge basin: see the module documentation.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Bed {
    /// The water surface at both ends (equal for a basin).
    pub a: [f64; 3],
    pub b: [f64; 3],
    /// Wetted half-width, metres.
    pub half_width: f64,
    /// Depth of water at the axis, metres.
    pub depth: f64,
    /// Slope of the banks above the water (rise over run).
    pub bank_slope: f64,
    /// The banks stop this far from the axis, metres.
    pub reach: f64,
}

/// A pool controller's basin: see the module documentation.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Basin {
    /// The outline of the water surface.
    pub outline: Outline,
    /// Water surface elevation, metres.
    pub level: f64,
    /// Depth of the flat floor below the level, metres.
    pub depth: f64,
    /// Slope of the sides, under and above the water (rise over run).
    pub bank_slope: f64,
    /// The banks stop this far outside the outline, metres.
    pub reach: f64,
}

/// A falling sheet's piece: the box along `a` → `b`, `width` across (horizontal) and
/// `thickness` through.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Sheet {
    pub a: [f64; 3],
    pub b: [f64; 3],
    pub width: f64,
    pub thickness: f64,
}

/// The water of a pool: under `level`, within its outline.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct PoolWater {
    pub level: f64,
    pub outline: Outline,
}

/// Everything the surface water adds to the model.
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
pub struct SurfacePieces {
    pub beds: Vec<Bed>,
    pub basins: Vec<Basin>,
    pub alcoves: Vec<Capsule>,
    pub sheets: Vec<Sheet>,
    pub pools: Vec<PoolWater>,
}

impl SurfacePieces {
    /// Finite pieces of positive size: what the carved terrain's 1-Lipschitz bound and the
    /// mesher's evaluations rely on.
    pub(crate) fn validate(&self) -> Result<(), Invalid> {
        for (i, bed) in self.beds.iter().enumerate() {
            let at = |f: &str| format!("surface.beds[{i}].{f}");
            check::position(|| at("a"), &bed.a)?;
            check::position(|| at("b"), &bed.b)?;
            check::positive(|| at("half_width"), bed.half_width, MAX_COORDINATE)?;
            check::within(|| at("depth"), bed.depth, 0.0, MAX_COORDINATE)?;
            check::positive(|| at("bank_slope"), bed.bank_slope, MAX_COORDINATE)?;
            check::positive(|| at("reach"), bed.reach, MAX_COORDINATE)?;
        }
        for (i, basin) in self.basins.iter().enumerate() {
            let at = |f: &str| format!("surface.basins[{i}].{f}");
            basin.outline.validate(&at("outline"))?;
            check::within(|| at("level"), basin.level, -MAX_COORDINATE, MAX_COORDINATE)?;
            check::within(|| at("depth"), basin.depth, 0.0, MAX_COORDINATE)?;
            check::positive(|| at("bank_slope"), basin.bank_slope, MAX_COORDINATE)?;
            check::positive(|| at("reach"), basin.reach, MAX_COORDINATE)?;
        }
        for (i, alcove) in self.alcoves.iter().enumerate() {
            alcove.validate(&|| format!("surface.alcoves[{i}]"))?;
        }
        for (i, sheet) in self.sheets.iter().enumerate() {
            let at = |f: &str| format!("surface.sheets[{i}].{f}");
            check::position(|| at("a"), &sheet.a)?;
            check::position(|| at("b"), &sheet.b)?;
            check::positive(|| at("width"), sheet.width, MAX_COORDINATE)?;
            check::positive(|| at("thickness"), sheet.thickness, MAX_COORDINATE)?;
        }
        for (i, pool) in self.pools.iter().enumerate() {
            pool.outline.validate(&format!("surface.pools[{i}].outline"))?;
            check::within(
                || format!("surface.pools[{i}].level"),
                pool.level,
                -MAX_COORDINATE,
                MAX_COORDINATE,
            )?;
        }
        Ok(())
    }
}

/// Pieces of the falling sheet along each parabola.
const SHEET_PIECES: usize = 12;
/// Water reaches this far beyond a bed's wetted edge, metres (it is held by the banks).
const SHORE: f64 = 0.25;

/// Adds the surface water of `streams` to `model`: its pieces, and the springs' mouths to the
/// karst's capsules. The one call the sdf stage makes with `streams.json`.
pub fn add(model: &mut crate::SdfModel, streams: &Streams, params: &StreamsParams) {
    let (surface, mouths) = pieces(streams, params);
    model.surface = surface;
    model.capsules.extend(mouths);
}

/// The pieces of `streams` (and the mouths: capsules to add to the karst).
pub fn pieces(streams: &Streams, params: &StreamsParams) -> (SurfacePieces, Vec<Capsule>) {
    let k = params.bank_slope;
    let mut out = SurfacePieces::default();
    let position = |n: u32| DVec3::from_array(streams.nodes[n as usize].position);
    for s in streams.segments.iter().filter(|s| s.flow > 0.0) {
        match s.motion {
            Motion::Contact => {
                let half_width = (0.5 * s.width).max(0.05);
                let depth = s.depth.max(0.02);
                out.beds.push(Bed {
                    a: position(s.from).to_array(),
                    b: position(s.to).to_array(),
                    half_width,
                    depth,
                    bank_slope: k,
                    reach: half_width + 3.0 / k,
                });
            }
            Motion::FreeFall => {
                if let Some(f) = &s.fall {
                    let points: Vec<DVec3> = (0..=SHEET_PIECES)
                        .map(|i| DVec3::from_array(f.at(f.throw * i as f64 / SHEET_PIECES as f64)))
                        .collect();
                    for w in points.windows(2) {
                        out.sheets.push(Sheet {
                            a: w[0].to_array(),
                            b: w[1].to_array(),
                            width: s.width.max(params.sheet_thickness),
                            thickness: s.depth.max(params.sheet_thickness),
                        });
                    }
                }
            }
            Motion::Pool => {}
        }
    }
    for pool in &streams.pools {
        match (&pool.outline, pool.kind) {
            (Outline::Disc { centre, radius }, PoolKind::Plunge) => {
                let c = [centre[0], centre[1], pool.level];
                out.beds.push(Bed {
                    a: c,
                    b: c,
                    half_width: *radius,
                    depth: pool.depth.max(0.1),
                    bank_slope: k,
                    reach: radius + 3.0 / k,
                });
                if let Some(alcove) = pool.fall.and_then(|f| alcove(streams, f as usize)) {
                    out.alcoves.push(alcove);
                }
            }
            (outline, kind) => {
                if kind == PoolKind::Curve {
                    out.basins.push(Basin {
                        outline: outline.clone(),
                        level: pool.level,
                        depth: pool.depth,
                        bank_slope: k,
                        reach: 3.0 / k,
                    });
                }
                out.pools.push(PoolWater { level: pool.level, outline: outline.clone() });
            }
        }
    }
    let mouths = streams
        .springs
        .iter()
        .filter_map(|s| s.mouth.map(|m| (s.position, m)))
        .filter(|(a, b)| DVec3::from_array(*a).distance(DVec3::from_array(*b)) > 1e-6)
        .map(|(a, b)| Capsule { a, b, radius: params.mouth_radius })
        .collect();
    (out, mouths)
}

/// The hollow under the lip of fall `segment`: a horizontal capsule across the fall, half
/// behind the lip, between the pool and the lip (at least 1.5 m of rock left above it).
fn alcove(streams: &Streams, segment: usize) -> Option<Capsule> {
    let s = streams.segments.get(segment)?;
    let f = s.fall.as_ref()?;
    let radius = (0.3 * f.drop).min(0.55 * f.drop - 1.5).min(4.0);
    if radius < 0.5 {
        return None;
    }
    let u = DVec2::from_array(f.direction);
    let across = u.perp();
    let centre = (DVec2::new(f.lip[0], f.lip[1]) - u * 0.5 * radius).extend(f.impact[2] + 0.45 * f.drop);
    let half = 0.5 * s.width + radius;
    let offset = across.extend(0.0) * (half - radius).max(0.0);
    Some(Capsule { a: (centre - offset).to_array(), b: (centre + offset).to_array(), radius })
}

impl Bed {
    /// Horizontal distance to the axis, and the water surface at the nearest axis point.
    fn frame(&self, p: DVec3) -> (f64, f64, f64) {
        let (a, b) = (DVec3::from_array(self.a), DVec3::from_array(self.b));
        let ab = (b - a).truncate();
        let length2 = ab.length_squared();
        let t = if length2 > 0.0 {
            ((p.truncate() - a.truncate()).dot(ab) / length2).clamp(0.0, 1.0)
        } else {
            0.0
        };
        let d = p.truncate().distance(a.truncate() + ab * t);
        let grade = if length2 > 0.0 { (b.z - a.z).abs() / length2.sqrt() } else { 0.0 };
        (d, a.z + t * (b.z - a.z), grade)
    }

    /// Carve value: negative in the air the bed opens.
    pub fn carve(&self, p: DVec3) -> f64 {
        let (d, surface, grade) = self.frame(p);
        let (w, k, z) = (self.half_width, self.bank_slope, self.depth);
        let s = d - w;
        let bed = surface + if s < 0.0 { (z / w * s).max(-z) } else { k * s };
        let lambda = grade + (z / w).max(k);
        ((bed - p.z) / (1.0 + lambda * lambda).sqrt()).max(d - self.reach)
    }

    /// Water value: negative under the water surface within the wetted width (and a shore).
    pub fn water(&self, p: DVec3) -> f64 {
        let (d, surface, grade) = self.frame(p);
        ((p.z - surface) / (1.0 + grade * grade).sqrt()).max(d - self.half_width - SHORE)
    }

    /// 2D bounds of the piece, `(lo, hi)`.
    fn bounds(&self) -> (DVec2, DVec2) {
        let (a, b) = (DVec2::new(self.a[0], self.a[1]), DVec2::new(self.b[0], self.b[1]));
        let r = self.reach.max(self.half_width + SHORE);
        (a.min(b) - DVec2::splat(r), a.max(b) + DVec2::splat(r))
    }
}

impl Basin {
    /// Carve value: negative in the air the basin opens.
    pub fn carve(&self, p: DVec3) -> f64 {
        let s = outline_distance(&self.outline, p.truncate());
        let k = self.bank_slope;
        let floor = self.level + (k * s).max(-self.depth);
        ((floor - p.z) / (1.0 + k * k).sqrt()).max(s - self.reach)
    }

    fn bounds(&self) -> (DVec2, DVec2) {
        let (lo, hi) = outline_bounds(&self.outline);
        (lo - DVec2::splat(self.reach), hi + DVec2::splat(self.reach))
    }
}

impl Sheet {
    pub fn water(&self, p: DVec3) -> f64 {
        let (a, b) = (DVec3::from_array(self.a), DVec3::from_array(self.b));
        let length = a.distance(b);
        let u = if length > 0.0 { (b - a) / length } else { DVec3::NEG_Z };
        let across = DVec3::new(-u.y, u.x, 0.0).try_normalize().unwrap_or(DVec3::X);
        let through = u.cross(across);
        let q = p - (a + b) * 0.5;
        // Lengthened by half a thickness so that consecutive pieces overlap at the joints.
        let half = DVec3::new(0.5 * (length + self.thickness), 0.5 * self.width, 0.5 * self.thickness);
        let local = DVec3::new(q.dot(u).abs(), q.dot(across).abs(), q.dot(through).abs()) - half;
        local.max(DVec3::ZERO).length() + local.max_element().min(0.0)
    }

    fn bounds(&self) -> (DVec2, DVec2) {
        let (a, b) = (DVec2::new(self.a[0], self.a[1]), DVec2::new(self.b[0], self.b[1]));
        let r = 0.5 * (self.width + self.thickness) + self.thickness;
        (a.min(b) - DVec2::splat(r), a.max(b) + DVec2::splat(r))
    }
}

impl PoolWater {
    pub fn water(&self, p: DVec3) -> f64 {
        (p.z - self.level).max(outline_distance(&self.outline, p.truncate()))
    }

    fn bounds(&self) -> (DVec2, DVec2) {
        outline_bounds(&self.outline)
    }
}

/// 2D bounds of an outline, `(lo, hi)`.
fn outline_bounds(outline: &Outline) -> (DVec2, DVec2) {
    let points: Vec<DVec2> = match outline {
        Outline::Disc { centre, radius } => {
            let c = DVec2::from_array(*centre);
            vec![c - DVec2::splat(*radius), c + DVec2::splat(*radius)]
        }
        Outline::Cells { rectangles } => {
            rectangles.iter().flat_map(|r| [DVec2::new(r[0], r[1]), DVec2::new(r[2], r[3])]).collect()
        }
        Outline::Polygon { points } => points.iter().map(|p| DVec2::from_array(*p)).collect(),
    };
    let lo = points.iter().copied().fold(DVec2::splat(f64::INFINITY), DVec2::min);
    let hi = points.iter().copied().fold(DVec2::splat(f64::NEG_INFINITY), DVec2::max);
    (lo, hi)
}

/// Signed 2D distance to an outline (negative inside; inside a union of rectangles, the depth
/// in the deepest one, which keeps the bound).
fn outline_distance(outline: &Outline, p: DVec2) -> f64 {
    match outline {
        Outline::Disc { centre, radius } => p.distance(DVec2::from_array(*centre)) - radius,
        Outline::Cells { rectangles } => rectangles.iter().fold(f64::INFINITY, |best, r| {
            let (lo, hi) = (DVec2::new(r[0], r[1]), DVec2::new(r[2], r[3]));
            let d = (lo - p).max(p - hi);
            // The larger axis gap is at most the rectangle's signed distance (equal inside):
            // most of a lake's rows stop at this test, before the root.
            if d.max_element() >= best {
                best
            } else {
                best.min(d.max(DVec2::ZERO).length() + d.max_element().min(0.0))
            }
        }),
        Outline::Polygon { points } => {
            let pts: Vec<DVec2> = points.iter().map(|q| DVec2::from_array(*q)).collect();
            let outside = karst_streams::polygon_distance(&pts, p);
            if outside > 0.0 {
                outside
            } else {
                -(0..pts.len())
                    .map(|k| {
                        let (a, b) = (pts[k], pts[(k + 1) % pts.len()]);
                        let ab = b - a;
                        let t = ((p - a).dot(ab) / ab.length_squared().max(1e-300)).clamp(0.0, 1.0);
                        p.distance(a + ab * t)
                    })
                    .fold(f64::INFINITY, f64::min)
            }
        }
    }
}

/// Which pieces can matter in each cell of a 2D grid.
#[derive(Debug, Clone, Default)]
struct Index {
    lo: DVec2,
    cell: f64,
    nx: usize,
    ny: usize,
    /// Piece ids per cell.
    cells: Vec<Vec<u32>>,
    /// Bounds of all pieces, `(lo, hi)`.
    all: Option<(DVec2, DVec2)>,
}

/// Cell edge of the index, metres.
const INDEX_CELL: f64 = 8.0;

impl Index {
    fn of(bounds: &[(DVec2, DVec2)]) -> Index {
        if bounds.is_empty() {
            return Index::default();
        }
        let lo = bounds.iter().map(|b| b.0).fold(DVec2::splat(f64::INFINITY), DVec2::min);
        let hi = bounds.iter().map(|b| b.1).fold(DVec2::splat(f64::NEG_INFINITY), DVec2::max);
        let (lo_grown, hi_grown) = (lo - DVec2::splat(REACH), hi + DVec2::splat(REACH));
        let cell = INDEX_CELL.max(((hi_grown - lo_grown).x * (hi_grown - lo_grown).y / 1e6).sqrt());
        let nx = ((hi_grown.x - lo_grown.x) / cell).ceil().max(1.0) as usize;
        let ny = ((hi_grown.y - lo_grown.y) / cell).ceil().max(1.0) as usize;
        let mut cells = vec![Vec::new(); nx * ny];
        for (id, (a, b)) in bounds.iter().enumerate() {
            let (i0, j0) = Self::coords(lo_grown, cell, *a - DVec2::splat(REACH));
            let (i1, j1) = Self::coords(lo_grown, cell, *b + DVec2::splat(REACH));
            for j in j0..=j1.min(ny - 1) {
                for i in i0..=i1.min(nx - 1) {
                    cells[j * nx + i].push(id as u32);
                }
            }
        }
        Index { lo: lo_grown, cell, nx, ny, cells, all: Some((lo, hi)) }
    }

    fn coords(lo: DVec2, cell: f64, p: DVec2) -> (usize, usize) {
        let q = ((p - lo) / cell).max(DVec2::ZERO);
        (q.x.floor() as usize, q.y.floor() as usize)
    }

    /// The pieces listed at `p`, and a lower bound of every unlisted piece's value.
    fn at(&self, p: DVec3) -> (&[u32], f64) {
        let Some((lo, hi)) = self.all else { return (&[], f64::INFINITY) };
        let d = (lo - p.truncate()).max(p.truncate() - hi);
        let outside = d.max(DVec2::ZERO).length();
        let floor = REACH.max(outside);
        let q = (p.truncate() - self.lo) / self.cell;
        if q.x < 0.0 || q.y < 0.0 || q.x >= self.nx as f64 || q.y >= self.ny as f64 {
            return (&[], floor);
        }
        (&self.cells[q.y as usize * self.nx + q.x as usize], floor)
    }
}

/// The surface pieces, ready to evaluate.
#[derive(Debug, Clone, Default)]
pub struct SurfaceField {
    pieces: SurfacePieces,
    /// The horizontal boxes of the pieces that carve the rock (beds, basins, alcoves).
    carve_bounds: Vec<(DVec2, DVec2)>,
    carves: Index,
    waters: Index,
}

impl SurfaceField {
    pub fn new(pieces: &SurfacePieces) -> SurfaceField {
        let carve_bounds: Vec<(DVec2, DVec2)> = pieces
            .beds
            .iter()
            .map(Bed::bounds)
            .chain(pieces.basins.iter().map(Basin::bounds))
            .chain(pieces.alcoves.iter().map(capsule_bounds))
            .collect();
        let water_bounds: Vec<(DVec2, DVec2)> = pieces
            .beds
            .iter()
            .map(Bed::bounds)
            .chain(pieces.sheets.iter().map(Sheet::bounds))
            .chain(pieces.pools.iter().map(PoolWater::bounds))
            .collect();
        SurfaceField {
            pieces: pieces.clone(),
            carves: Index::of(&carve_bounds),
            carve_bounds,
            waters: Index::of(&water_bounds),
        }
    }

    pub fn is_empty(&self) -> bool {
        self.carves.all.is_none() && self.waters.all.is_none()
    }

    /// Whether a piece that carves the rock has its horizontal box within `margin` of the
    /// horizontal box [lo, hi].
    pub fn carves_within(&self, lo: DVec2, hi: DVec2, margin: f64) -> bool {
        self.carve_bounds.iter().any(|&(a, b)| (a - hi).max(lo - b).max(DVec2::ZERO).length() < margin)
    }

    /// The air the surface water opens in the rock: negative inside; min(REACH or farther, ·).
    pub fn carve(&self, p: DVec3) -> f64 {
        let (ids, floor) = self.carves.at(p);
        let (beds, basins) = (self.pieces.beds.len(), self.pieces.basins.len());
        ids.iter()
            .map(|&id| {
                let id = id as usize;
                if id < beds {
                    self.pieces.beds[id].carve(p)
                } else if id < beds + basins {
                    self.pieces.basins[id - beds].carve(p)
                } else {
                    self.pieces.alcoves[id - beds - basins].distance(p)
                }
            })
            .fold(floor, f64::min)
    }

    /// The surface water pieces: negative inside (before clipping to the air).
    pub fn water(&self, p: DVec3) -> f64 {
        let (ids, floor) = self.waters.at(p);
        let (beds, sheets) = (self.pieces.beds.len(), self.pieces.sheets.len());
        ids.iter()
            .map(|&id| {
                let id = id as usize;
                if id < beds {
                    self.pieces.beds[id].water(p)
                } else if id < beds + sheets {
                    self.pieces.sheets[id - beds].water(p)
                } else {
                    self.pieces.pools[id - beds - sheets].water(p)
                }
            })
            .fold(floor, f64::min)
    }
}

fn capsule_bounds(c: &Capsule) -> (DVec2, DVec2) {
    let (lo, hi) = c.bounds();
    (lo.truncate(), hi.truncate())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::testing::{Pairs, assert_lipschitz};

    fn field() -> SurfaceField {
        let bed = |a: [f64; 3], b: [f64; 3], w: f64, z: f64| Bed {
            a,
            b,
            half_width: w,
            depth: z,
            bank_slope: 1.0,
            reach: w + 3.0,
        };
        SurfaceField::new(&SurfacePieces {
            beds: vec![
                bed([0.0, 0.0, 10.0], [10.0, 3.0, 8.0], 1.5, 0.4),
                bed([10.0, 3.0, 8.0], [14.0, 4.0, 5.0], 0.5, 0.2),
                bed([20.0, 4.0, 2.0], [20.0, 4.0, 2.0], 4.0, 1.5),
            ],
            basins: vec![Basin {
                outline: Outline::Polygon {
                    points: vec![[50.0, 0.0], [58.0, 1.0], [56.0, 8.0], [51.0, 6.0]],
                },
                level: 3.0,
                depth: 1.2,
                bank_slope: 1.0,
                reach: 3.0,
            }],
            alcoves: vec![Capsule { a: [16.0, 2.0, 4.0], b: [16.0, 6.0, 4.0], radius: 1.5 }],
            sheets: vec![Sheet { a: [14.0, 4.0, 5.0], b: [16.0, 4.0, 2.0], width: 1.0, thickness: 0.5 }],
            pools: vec![
                PoolWater {
                    level: 1.0,
                    outline: Outline::Cells {
                        rectangles: vec![[30.0, 0.0, 34.0, 2.0], [30.0, 2.0, 36.0, 4.0]],
                    },
                },
                PoolWater {
                    level: 1.5,
                    outline: Outline::Polygon {
                        points: vec![[40.0, 0.0], [46.0, 1.0], [44.0, 6.0], [41.0, 5.0]],
                    },
                },
            ],
        })
    }

    #[test]
    fn the_pieces_are_one_lipschitz() {
        let f = field();
        for around in [DVec3::new(20.0, 3.0, 5.0), DVec3::new(54.0, 4.0, 3.0)] {
            assert_lipschitz(|p| f.carve(p), Pairs::new(11, 30.0, 3.0).around(around), 20_000);
            assert_lipschitz(|p| f.water(p), Pairs::new(12, 30.0, 3.0).around(around), 20_000);
        }
    }

    #[test]
    fn a_bed_holds_its_water_below_its_banks() {
        let f = field();
        // On the axis: air down to the depth, water up to the surface.
        let axis = DVec3::new(5.0, 1.5, 9.0);
        assert!(f.carve(axis - DVec3::Z * 0.3) < 0.0 && f.carve(axis - DVec3::Z * 0.5) > 0.0);
        assert!(f.water(axis - DVec3::Z * 0.1) < 0.0 && f.water(axis + DVec3::Z * 0.1) > 0.0);
        // The plunge basin is 1.5 m deep at its centre.
        assert!(f.carve(DVec3::new(20.0, 4.0, 0.6)) < 0.0 && f.carve(DVec3::new(20.0, 4.0, 0.4)) > 0.0);
        // The pool controller's basin: a flat floor 1.2 m under its level inside, sides at the
        // bank slope (the floor is 0.5 m down 0.5 m inside the shore), banks above the level.
        let centre = DVec3::new(54.0, 4.0, 0.0);
        assert!(f.carve(centre.with_z(1.9)) < 0.0 && f.carve(centre.with_z(1.7)) > 0.0);
        let inshore = DVec3::new(54.0, 0.5 + 0.5 * 65f64.sqrt() / 8.0, 0.0);
        assert!(
            f.carve(inshore.with_z(2.6)) < 0.0 && f.carve(inshore.with_z(2.4)) > 0.0,
            "{}",
            f.carve(inshore.with_z(2.4))
        );
        // Far away nothing is carved, and the value grows with the distance.
        assert!(f.carve(DVec3::new(200.0, 4.0, 0.0)) >= 130.0);
        assert!(SurfaceField::new(&SurfacePieces::default()).is_empty());
    }
}
