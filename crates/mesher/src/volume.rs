//! The solids the mesher polygonizes: the carved rock (the terrain with its caves) and the cave
//! alone (the karst volume, what artists want). Both are 1-Lipschitz fields, negative inside
//! the solid, so the octree's exclusion test |f(centre)| > half diagonal is exact for both.

use glam::DVec3;

use karst_sdf::CarvedTerrain;

/// A solid given by a 1-Lipschitz field, negative inside.
pub trait Volume: Sync {
    /// The field at p.
    fn eval(&self, p: DVec3) -> f64;

    /// The field where |f(p)| < `reach`; elsewhere any value of the same sign and magnitude at
    /// least `reach` (cheaper for fields that search for their nearest primitive).
    fn eval_within(&self, p: DVec3, _reach: f64) -> f64 {
        self.eval(p)
    }

    /// [`Volume::eval_within`] at `points`, all inside the box [lo, hi], appended to `out`.
    /// Fields that search for their nearest primitive gather the candidates of the box once.
    fn eval_block(&self, lo: DVec3, hi: DVec3, reach: f64, points: &[DVec3], out: &mut Vec<f64>) {
        let _ = (lo, hi);
        out.extend(points.iter().map(|&p| self.eval_within(p, reach)));
    }

    /// A lower bound of |f| over the box [lo, hi] (0 when the surface may cross it).
    fn bound(&self, lo: DVec3, hi: DVec3) -> f64 {
        let half_diagonal = (hi - lo).length() * 0.5;
        (self.eval_within((lo + hi) * 0.5, half_diagonal * 1.001).abs() - half_diagonal).max(0.0)
    }

    /// [`Volume::bound`] of each of `boxes`, all inside the box [lo, hi], into `out` (one per
    /// box). Fields that search for their nearest primitive gather the candidates of [lo, hi]
    /// once ([`bounds_near`]).
    fn bounds(&self, lo: DVec3, hi: DVec3, boxes: &[(DVec3, DVec3)], out: &mut [f64]) {
        let _ = (lo, hi);
        for (o, &(l, h)) in out.iter_mut().zip(boxes) {
            *o = self.bound(l, h);
        }
    }

    /// The box the solid lies in, `(lo, hi)`.
    fn extent(&self) -> (DVec3, DVec3);
}

/// [`Volume::bounds`] as the default [`Volume::bound`] computes them, from `value(p, reach)`,
/// the field's [`Volume::eval_within`] at the boxes' centres evaluated with the largest of the
/// boxes' reaches (the candidates near [lo, hi] gathered once for it). Where a box's own reach
/// would give an exact value this one is exact too, the same bits; elsewhere both bounds are
/// positive: the octree keeps the same boxes.
fn bounds_near(boxes: &[(DVec3, DVec3)], out: &mut [f64], mut value: impl FnMut(DVec3, f64) -> f64) {
    let half = |&(l, h): &(DVec3, DVec3)| (h - l).length() * 0.5;
    let reach = boxes.iter().map(|b| half(b) * 1.001).fold(0.0, f64::max);
    for (o, b) in out.iter_mut().zip(boxes) {
        *o = (value((b.0 + b.1) * 0.5, reach).abs() - half(b)).max(0.0);
    }
}

/// The carved rock: inside is rock, outside is air (sky, caves, beyond the domain).
impl Volume for CarvedTerrain {
    fn eval(&self, p: DVec3) -> f64 {
        CarvedTerrain::eval(self, p)
    }

    fn eval_within(&self, p: DVec3, reach: f64) -> f64 {
        CarvedTerrain::eval_within(self, p, reach)
    }

    fn eval_block(&self, lo: DVec3, hi: DVec3, reach: f64, points: &[DVec3], out: &mut Vec<f64>) {
        let near = self.near(lo, hi, reach);
        out.extend(points.iter().map(|&p| self.eval_near(&near, p, reach)));
    }

    fn bounds(&self, lo: DVec3, hi: DVec3, boxes: &[(DVec3, DVec3)], out: &mut [f64]) {
        let mut near = None;
        bounds_near(boxes, out, |p, reach| {
            self.eval_near(near.get_or_insert_with(|| self.near(lo, hi, reach)), p, reach)
        });
    }

    fn extent(&self) -> (DVec3, DVec3) {
        let domain = &self.model().domain;
        (domain.min(), domain.max())
    }
}

/// The cave alone: inside is the karst volume below the ground.
#[derive(Debug, Clone, Copy)]
pub struct Cave<'a>(pub &'a CarvedTerrain);

impl Volume for Cave<'_> {
    fn eval(&self, p: DVec3) -> f64 {
        self.0.cave_below_ground(p, f64::INFINITY)
    }

    fn eval_within(&self, p: DVec3, reach: f64) -> f64 {
        self.0.cave_below_ground(p, reach)
    }

    fn eval_block(&self, lo: DVec3, hi: DVec3, reach: f64, points: &[DVec3], out: &mut Vec<f64>) {
        let near = self.0.near_cave(lo, hi, reach);
        out.extend(points.iter().map(|&p| self.0.cave_below_ground_near(&near, p, reach)));
    }

    fn bounds(&self, lo: DVec3, hi: DVec3, boxes: &[(DVec3, DVec3)], out: &mut [f64]) {
        let mut near = None;
        bounds_near(boxes, out, |p, reach| {
            self.0.cave_below_ground_near(
                near.get_or_insert_with(|| self.0.near_cave(lo, hi, reach)),
                p,
                reach,
            )
        });
    }

    fn extent(&self) -> (DVec3, DVec3) {
        self.0.extent()
    }
}

/// The water: inside is the water held in the conduits (`CarvedTerrain::water`, which stays
/// inside the karst volume).
#[derive(Debug, Clone, Copy)]
pub struct Water<'a>(pub &'a CarvedTerrain);

impl Volume for Water<'_> {
    fn eval(&self, p: DVec3) -> f64 {
        self.0.water(p)
    }

    fn eval_within(&self, p: DVec3, reach: f64) -> f64 {
        self.0.water_within(p, reach)
    }

    fn eval_block(&self, lo: DVec3, hi: DVec3, reach: f64, points: &[DVec3], out: &mut Vec<f64>) {
        let near = self.0.near_water(lo, hi, reach);
        out.extend(points.iter().map(|&p| self.0.water_near(&near, p, reach)));
    }

    fn bounds(&self, lo: DVec3, hi: DVec3, boxes: &[(DVec3, DVec3)], out: &mut [f64]) {
        let mut near = None;
        bounds_near(boxes, out, |p, reach| {
            self.0.water_near(near.get_or_insert_with(|| self.0.near_water(lo, hi, reach)), p, reach)
        });
    }

    fn extent(&self) -> (DVec3, DVec3) {
        self.0.extent()
    }
}

/// A borrowed solid is the same solid.
impl<V: Volume + ?Sized> Volume for &V {
    fn eval(&self, p: DVec3) -> f64 {
        (**self).eval(p)
    }

    fn eval_within(&self, p: DVec3, reach: f64) -> f64 {
        (**self).eval_within(p, reach)
    }

    fn eval_block(&self, lo: DVec3, hi: DVec3, reach: f64, points: &[DVec3], out: &mut Vec<f64>) {
        (**self).eval_block(lo, hi, reach, points, out)
    }

    fn bound(&self, lo: DVec3, hi: DVec3) -> f64 {
        (**self).bound(lo, hi)
    }

    fn bounds(&self, lo: DVec3, hi: DVec3, boxes: &[(DVec3, DVec3)], out: &mut [f64]) {
        (**self).bounds(lo, hi, boxes, out)
    }

    fn extent(&self) -> (DVec3, DVec3) {
        (**self).extent()
    }
}
