//! Evaluating the field of an [`SdfModel`].

use glam::DVec3;

use crate::SdfModel;
use crate::bvh::Bvh;

/// The carved terrain's signed-distance bound, ready to evaluate.
#[derive(Debug, Clone)]
pub struct CarvedTerrain {
    model: SdfModel,
    bvh: Bvh,
}

impl CarvedTerrain {
    pub fn new(model: SdfModel) -> Self {
        let bvh = Bvh::build(&model.capsules);
        CarvedTerrain { model, bvh }
    }

    pub fn model(&self) -> &SdfModel {
        &self.model
    }

    /// Rock before the caves: below the terrain and inside the domain (negative inside).
    fn uncarved(&self, p: DVec3) -> f64 {
        self.model.terrain.distance(p).max(self.model.domain.signed_distance(p))
    }

    /// f(p): negative in rock, positive in air; 1-Lipschitz.
    pub fn eval(&self, p: DVec3) -> f64 {
        let rock = self.uncarved(p);
        // Caves matter only where they go deeper than −rock: max(rock, −min(−rock, caves)).
        let caves = self.bvh.min_distance(&self.model.capsules, p, -rock);
        rock.max(-caves)
    }

    /// The cave alone: the karst volume clipped to the rock under the terrain and inside the
    /// domain, negative inside the cave. Exact where its magnitude is below `reach`; elsewhere
    /// a value of the same sign and magnitude at least `reach`, so that the search for the
    /// nearest conduit can stop at `reach` (the mesher asks for a cell or a half diagonal).
    pub fn cave(&self, p: DVec3, reach: f64) -> f64 {
        let rock = self.uncarved(p);
        if rock >= reach {
            return rock;
        }
        self.bvh.min_distance(&self.model.capsules, p, reach).max(rock)
    }

    /// A guaranteed lower bound of |f| over the box [lo, hi] (0 when the surface may cross it).
    pub fn bound(&self, lo: DVec3, hi: DVec3) -> f64 {
        let centre = (lo + hi) * 0.5;
        (self.eval(centre).abs() - (hi - lo).length() * 0.5).max(0.0)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::Capsule;
    use crate::terrain::TerrainField;
    use karst_geology::Domain;

    fn field() -> CarvedTerrain {
        CarvedTerrain::new(SdfModel {
            domain: Domain { min: [0.0, 0.0, 0.0], max: [100.0, 100.0, 50.0] },
            terrain: TerrainField::Plane { elevation: 40.0, origin: [0.0, 0.0], gradient: [0.1, 0.0] },
            capsules: vec![Capsule { a: [20.0, 50.0, 20.0], b: [80.0, 50.0, 20.0], radius: 3.0 }],
        })
    }

    #[test]
    fn sign_follows_rock_and_air() {
        let f = field();
        assert!(f.eval(DVec3::new(50.0, 50.0, 20.0)) > 0.0, "inside the cave");
        assert!(f.eval(DVec3::new(50.0, 20.0, 20.0)) < 0.0, "in rock");
        assert!(f.eval(DVec3::new(50.0, 20.0, 49.0)) > 0.0, "above the ground");
        assert!(f.eval(DVec3::new(-1.0, 20.0, 20.0)) > 0.0, "outside the domain");
    }

    #[test]
    fn is_one_lipschitz() {
        let f = field();
        let mut state = 7u64;
        let mut next = || {
            state = state.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
            (state >> 11) as f64 / (1u64 << 53) as f64
        };
        for _ in 0..5000 {
            let p = DVec3::new(next() * 120.0 - 10.0, next() * 120.0 - 10.0, next() * 70.0 - 10.0);
            let q = p + DVec3::new(next() - 0.5, next() - 0.5, next() - 0.5) * 8.0;
            assert!((f.eval(p) - f.eval(q)).abs() <= p.distance(q) * (1.0 + 1e-9));
        }
    }
}
