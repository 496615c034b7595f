//! Removing rock islands floating in cave air and air pockets sealed in rock (Cui et al. 2011,
//! §3.2–3.3: floating islands are dropped, then a flood fill from the cave keeps only the air
//! connected to it).
//!
//! The flood fill is done on the closed surface rather than on voxels: every connected
//! component of a closed, outward-oriented 2-manifold mesh bounds one connected piece of the
//! solid (positive enclosed volume) or one hole in it (negative volume). Hence:
//! - carved rock: a piece of rock is kept when it reaches the domain box (it stands on the
//!   floor or leans on a side; the box is where the model's rock ends), otherwise it is an
//!   island hanging in cave air. A hole in the rock is air that reaches neither the sky nor a
//!   domain face, so it is a sealed pocket, kept only when it holds a sink or a spring;
//! - cave alone: a hole in the karst volume is rock surrounded by cave air, an island; a piece
//!   of cave is kept when it reaches the ground or a domain face (it opens to the outside) or
//!   holds a sink or a spring (encloses it or passes within a cell of it), otherwise it is a
//!   sealed pocket.
//!
//! "Reaches" means a vertex within a quarter cell of the boundary: the polygonizer puts the
//! vertices of a surface that meets the boundary on it, up to the interpolation clamp.

use glam::DVec3;

use karst_sdf::SdfModel;

use crate::components;
use crate::payload::{Removed, TriMesh};

/// Which solid a surface bounds.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Solid {
    /// The carved terrain: rock inside.
    Rock,
    /// The cave alone: karst volume inside.
    Cave,
}

/// What a component is.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Verdict {
    Keep,
    Island,
    Pocket,
}

/// Removes islands and pockets from `surface` in place; `anchors` are the sinks and springs.
pub fn clean(surface: &mut TriMesh, solid: Solid, model: &SdfModel, anchors: &[DVec3], cell_size: f64) {
    let (labels, count) = components::label(surface);
    let mut volume = vec![0.0; count];
    let mut reaches = vec![false; count];
    let reach = Reach::new(solid, model, cell_size);
    for (t, &c) in surface.triangles.iter().zip(&labels) {
        volume[c as usize] += surface.volume_of(std::iter::once(t));
        reaches[c as usize] |= t.iter().any(|&v| reach.reaches(surface.position(v)));
    }
    let holds_anchor = |c: usize| anchors.iter().any(|&a| holds(surface, &labels, c as u32, a, cell_size));
    let verdicts: Vec<Verdict> =
        (0..count).map(|c| verdict(solid, volume[c], reaches[c], || holds_anchor(c))).collect();
    surface.removed = removed(&verdicts, &volume);
    if verdicts.iter().any(|&v| v != Verdict::Keep) {
        retain(surface, |t| verdicts[labels[t] as usize] == Verdict::Keep);
    }
}

/// Whether a vertex lies on the boundary the solid's components must reach to be kept: within
/// a quarter cell of the domain box (rock), of the box or the ground (cave).
pub(crate) struct Reach<'m> {
    solid: Solid,
    model: &'m SdfModel,
    near: f64,
}

impl<'m> Reach<'m> {
    pub(crate) fn new(solid: Solid, model: &'m SdfModel, cell_size: f64) -> Self {
        Reach { solid, model, near: -0.25 * cell_size }
    }

    pub(crate) fn reaches(&self, p: DVec3) -> bool {
        let boundary = match self.solid {
            Solid::Rock => self.model.domain.signed_distance(p),
            Solid::Cave => self.model.domain.signed_distance(p).max(self.model.terrain.distance(p)),
        };
        boundary > self.near
    }
}

/// The verdict on a component of enclosed `volume` (positive: a piece of the solid, else a
/// hole in it) that reaches the boundary or not; `holds_anchor` is asked only when it matters.
pub(crate) fn verdict(solid: Solid, volume: f64, reaches: bool, holds_anchor: impl Fn() -> bool) -> Verdict {
    match (solid, volume > 0.0) {
        (Solid::Rock, true) if !reaches => Verdict::Island,
        (Solid::Rock, false) if !holds_anchor() => Verdict::Pocket,
        (Solid::Cave, false) => Verdict::Island,
        (Solid::Cave, true) if !reaches && !holds_anchor() => Verdict::Pocket,
        _ => Verdict::Keep,
    }
}

/// Whether the anchors decide a component's verdict: a hole in the rock, or a piece of cave
/// that does not reach the boundary.
pub(crate) fn asks_anchors(solid: Solid, volume: f64, reaches: bool) -> bool {
    match solid {
        Solid::Rock => volume <= 0.0,
        Solid::Cave => volume > 0.0 && !reaches,
    }
}

/// What the verdicts remove: counts and volumes, summed in component order.
pub(crate) fn removed(verdicts: &[Verdict], volume: &[f64]) -> Removed {
    let mut removed = Removed::default();
    for (c, verdict) in verdicts.iter().enumerate() {
        match verdict {
            Verdict::Island => {
                removed.islands += 1;
                removed.island_volume += volume[c].abs();
            }
            Verdict::Pocket => {
                removed.pockets += 1;
                removed.pocket_volume += volume[c].abs();
            }
            Verdict::Keep => {}
        }
    }
    removed
}

/// Whether component `c` holds the anchor `p`: encloses it, or passes within a cell of it. The
/// surface is resolved to a cell only: a sink just under the ground or a spring on a conduit's
/// end may fall just outside the polygonized surface of the passage it opens, which must not
/// make the whole cave a sealed pocket.
fn holds(surface: &TriMesh, labels: &[u32], c: u32, p: DVec3, cell_size: f64) -> bool {
    let corners = |t: &[u32; 3]| t.map(|v| surface.position(v));
    let near =
        surface.triangles.iter().zip(labels).any(|(t, &l)| l == c && touches(corners(t), p, cell_size));
    near || encloses(surface, labels, c, p)
}

/// Whether a corner of the triangle lies within `cell_size` of `p`.
pub(crate) fn touches(corners: [DVec3; 3], p: DVec3, cell_size: f64) -> bool {
    corners.iter().any(|v| v.distance_squared(p) <= cell_size * cell_size)
}

/// Whether component `c` encloses `p`: parity of the crossings of a ray from p. The ray's
/// direction is irrational in every axis so that it does not run along lattice planes.
fn encloses(surface: &TriMesh, labels: &[u32], c: u32, p: DVec3) -> bool {
    let direction = ray();
    let crossings = surface
        .triangles
        .iter()
        .zip(labels)
        .filter(|&(t, &l)| l == c && crosses(t.map(|v| surface.position(v)), p, direction))
        .count();
    crossings % 2 == 1
}

/// The direction of the rays cast from the anchors.
pub(crate) fn ray() -> DVec3 {
    DVec3::new(1.0, 2f64.sqrt() * 1e-3, 3f64.sqrt() * 1e-3).normalize()
}

/// Möller–Trumbore: does the ray p + s·d, s > 0, cross the triangle?
pub(crate) fn crosses([a, b, c]: [DVec3; 3], p: DVec3, d: DVec3) -> bool {
    let (e1, e2) = (b - a, c - a);
    let h = d.cross(e2);
    let det = e1.dot(h);
    if det.abs() < 1e-15 {
        return false;
    }
    let s = p - a;
    let u = s.dot(h) / det;
    let q = s.cross(e1);
    let v = d.dot(q) / det;
    u >= 0.0 && v >= 0.0 && u + v <= 1.0 && e2.dot(q) / det > 0.0
}

/// Keeps the triangles `keep` accepts (by index) and the vertices they use, in their order,
/// in place: no second copy of the surface.
fn retain(surface: &mut TriMesh, keep: impl Fn(usize) -> bool) {
    let mut t = 0;
    surface.triangles.retain(|_| {
        t += 1;
        keep(t - 1)
    });
    const UNUSED: u32 = u32::MAX;
    let mut renumber = vec![UNUSED; surface.vertices.len()];
    for &v in surface.triangles.iter().flatten() {
        renumber[v as usize] = 0;
    }
    let mut kept = 0;
    for (i, number) in renumber.iter_mut().enumerate() {
        if *number != UNUSED {
            *number = kept;
            surface.vertices[kept as usize] = surface.vertices[i];
            kept += 1;
        }
    }
    surface.vertices.truncate(kept as usize);
    for t in &mut surface.triangles {
        *t = t.map(|v| renumber[v as usize]);
    }
}
