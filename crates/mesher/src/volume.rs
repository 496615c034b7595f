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

    /// The box the solid lies in, `(lo, hi)`.
    fn extent(&self) -> (DVec3, DVec3);
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

    fn extent(&self) -> (DVec3, DVec3) {
        (**self).extent()
    }
}
