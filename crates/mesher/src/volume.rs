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
    /// once ([`bounds_from`]).
    fn bounds(&self, lo: DVec3, hi: DVec3, boxes: &[(DVec3, DVec3)], out: &mut [f64]) {
        let _ = (lo, hi);
        for (o, &(l, h)) in out.iter_mut().zip(boxes) {
            *o = self.bound(l, h);
        }
    }

    /// The box the solid lies in, `(lo, hi)`.
    fn extent(&self) -> (DVec3, DVec3);
}

/// The reach the boxes' bounds are evaluated with: the largest half diagonal among them (a
/// little more, so that a value exactly at it is not taken for a capped one).
fn widest_reach(boxes: &[(DVec3, DVec3)]) -> f64 {
    boxes.iter().map(|&(l, h)| (h - l).length() * 0.5 * 1.001).fold(0.0, f64::max)
}

/// [`Volume::bound`] as the volume's [`Volume::bounds`] gives it for the one box.
fn bound_of_one(volume: &impl Volume, lo: DVec3, hi: DVec3) -> f64 {
    let mut out = [0.0];
    volume.bounds(lo, hi, &[(lo, hi)], &mut out);
    out[0]
}

/// [`Volume::bounds`] as the default [`Volume::bound`] computes them, from `value(p, reach)`,
/// the field's [`Volume::eval_within`] at the boxes' centres evaluated with the largest of the
/// boxes' reaches (the candidates near [lo, hi] gathered once for it): where a box's own reach
/// would give an exact value this one is exact too, elsewhere both bounds are positive, so the
/// octree keeps the same boxes. Before that, `floor(lo, hi)`: a lower bound of the field over a
/// box that is positive only where the box holds none of the solid (0: no such test).
fn bounds_from(
    boxes: &[(DVec3, DVec3)],
    out: &mut [f64],
    floor: impl Fn(DVec3, DVec3) -> f64,
    mut value: impl FnMut(DVec3, f64) -> f64,
) {
    let reach = widest_reach(boxes);
    for (o, &(l, h)) in out.iter_mut().zip(boxes) {
        let free = floor(l, h);
        *o = if free > 0.0 {
            free
        } else {
            (value((l + h) * 0.5, reach).abs() - (h - l).length() * 0.5).max(0.0)
        };
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
        bounds_from(
            boxes,
            out,
            |_, _| 0.0,
            |p, reach| self.eval_near(near.get_or_insert_with(|| self.near(lo, hi, reach)), p, reach),
        );
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

    fn bound(&self, lo: DVec3, hi: DVec3) -> f64 {
        bound_of_one(self, lo, hi)
    }

    /// The boxes that no conduit reaches into by [`CarvedTerrain::cave_floor`], the others by
    /// the value at their centres.
    fn bounds(&self, lo: DVec3, hi: DVec3, boxes: &[(DVec3, DVec3)], out: &mut [f64]) {
        let near = self.0.near_cave(lo, hi, widest_reach(boxes));
        bounds_from(
            boxes,
            out,
            |l, h| self.0.cave_floor(&near, l, h),
            |p, reach| self.0.cave_below_ground_near(&near, p, reach),
        );
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

    fn bound(&self, lo: DVec3, hi: DVec3) -> f64 {
        bound_of_one(self, lo, hi)
    }

    /// The boxes that no conduit's water nor surface water reaches into by
    /// [`CarvedTerrain::water_floor`], the others by the value at their centres.
    fn bounds(&self, lo: DVec3, hi: DVec3, boxes: &[(DVec3, DVec3)], out: &mut [f64]) {
        let near = self.0.near_water(lo, hi, widest_reach(boxes));
        bounds_from(
            boxes,
            out,
            |l, h| self.0.water_floor(&near, l, h),
            |p, reach| self.0.water_near(&near, p, reach),
        );
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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::polygonize::polygonize;
    use karst_geology::Domain;
    use karst_sdf::{Capsule, SdfModel, TerrainField};

    /// One 2 m conduit across a block of rock 400 m wide and 200 m deep.
    fn one_conduit() -> CarvedTerrain {
        CarvedTerrain::new(SdfModel {
            capsules: vec![Capsule { a: [150.0, 200.0, 100.0], b: [250.0, 200.0, 100.0], radius: 2.0 }],
            ..SdfModel::new(
                Domain { min: [0.0, 0.0, 0.0], max: [400.0, 400.0, 220.0] },
                TerrainField::Plane { elevation: 200.0, origin: [0.0, 0.0], gradient: [0.0, 0.0] },
            )
        })
    }

    #[test]
    fn a_box_of_rock_far_wider_than_the_karsts_reach_is_proved_free_of_cave_and_water() {
        let field = one_conduit();
        // 100 m boxes: the karst's value at their centres is capped at 8 m, far below their
        // half diagonals; the conduit's leaf box is what proves them empty.
        let (lo, hi) = (DVec3::new(0.0, 0.0, 0.0), DVec3::new(100.0, 100.0, 100.0));
        assert!(Cave(&field).bound(lo, hi) > 0.0);
        assert!(Water(&field).bound(lo, hi) > 0.0);
        let mut out = [0.0; 2];
        let holding = (DVec3::new(140.0, 150.0, 50.0), DVec3::new(240.0, 250.0, 150.0));
        Cave(&field).bounds(DVec3::ZERO, DVec3::splat(400.0), &[(lo, hi), holding], &mut out);
        assert!(out[0] > 0.0);
        assert_eq!(out[1], 0.0, "the box the conduit crosses may hold the surface");
    }

    #[test]
    fn the_octree_spends_its_evaluations_near_the_conduit_not_in_the_rock() {
        let field = one_conduit();
        let cave = polygonize(&Cave(&field), 1.0);
        assert!(!cave.vertices.is_empty());
        // 5.6 per vertex. Before the boxes were bounded by the leaves' boxes, every box of rock
        // more than 16 m wide was split: 68 per vertex here, and the more so the larger the
        // domain is beside its conduits.
        assert!(cave.evaluations_per_vertex() < 15.0, "{}", cave.evaluations_per_vertex());
    }
}
