//! Evaluating the construction tree of an [`SdfModel`]:
//!
//! - rock(p) = max(terrain(p), domain(p)), negative in the bedrock before karstification;
//! - cave(p) = min(REACH, min over the karst leaves (sweeps, spheres, chambers, capsules)),
//!   negative in the karst volume K;
//! - eval(p) = −smooth_union(−rock(p), cave(p), blend): the terrain minus K, rounded by `blend`
//!   where conduits open to the surface; negative in rock, positive in air;
//! - water(p) = max(min(REACH, min over water pieces), cave(p)): negative in the water, which
//!   stays inside K.
//!
//! All are 1-Lipschitz (see [`crate::ops`]). The union over leaves runs through the BVH and only
//! needs the leaves that can go below −rock + blend; everything else cannot change eval.

use glam::DVec3;

use crate::bvh::Bvh;
use crate::chamber::Chamber;
use crate::model::detail_factor;
use crate::primitive::{Context, Leaf, WaterLeaf};
use crate::sweep::SweepTable;
use crate::{SdfModel, ops};
use karst_skeleton::ConduitType;

/// The karst terms are clamped to at most this many metres: min(cave, REACH) keeps the sign and
/// the Lipschitz bound (a smaller |f| is still a distance bound), and spares eval every leaf
/// farther away: a point deep in rock visits only the leaves within REACH.
pub const REACH: f64 = 8.0;

/// The carved terrain's signed-distance bound, ready to evaluate.
#[derive(Debug, Clone)]
pub struct CarvedTerrain {
    model: SdfModel,
    caves: Bvh,
    water: Bvh,
    /// The nodes and sections of the sweeps and water pieces.
    sweeps: SweepTable,
    /// Detail amplitude per conduit type.
    amplitude: [f64; 8],
    /// The terrain leaf's 1/√(1 + λ²), computed once rather than at every evaluation.
    terrain_scale: f64,
}

impl CarvedTerrain {
    pub fn new(model: SdfModel) -> Self {
        let mut amplitude = [0.0; 8];
        for kind in ConduitType::ALL {
            amplitude[kind as usize] = model.detail * detail_factor(kind);
        }
        let mut sweeps = SweepTable::default();
        let karst = karst_leaves(&model, &mut sweeps);
        let water = water_leaves(&model, &mut sweeps);
        let ctx =
            Context::new(&model.detail_noise, &model.chamber_noise, model.chamber_bias, &sweeps, &amplitude);
        let caves = Bvh::build(karst, &ctx);
        let water = Bvh::build(water, &ctx);
        let terrain_scale = model.terrain.scale();
        CarvedTerrain { model, caves, water, sweeps, amplitude, terrain_scale }
    }

    pub fn model(&self) -> &SdfModel {
        &self.model
    }

    fn context(&self) -> Context<'_> {
        Context::new(
            &self.model.detail_noise,
            &self.model.chamber_noise,
            self.model.chamber_bias,
            &self.sweeps,
            &self.amplitude,
        )
    }

    /// Rock before the caves: below the terrain and inside the domain (negative inside).
    fn uncarved(&self, p: DVec3) -> f64 {
        let terrain = (p.z - self.model.terrain.height(p.x, p.y)) * self.terrain_scale;
        terrain.max(self.model.domain.signed_distance(p))
    }

    /// f(p): negative in rock, positive in air; 1-Lipschitz.
    pub fn eval(&self, p: DVec3) -> f64 {
        let rock = self.uncarved(p);
        let blend = self.model.blend;
        // The smooth union equals −rock wherever the caves stay above −rock + blend.
        let caves = self.caves.min_value(p, (-rock + blend).min(REACH), &self.context());
        -ops::smooth_union(-rock, caves, blend)
    }

    /// The karst volume alone: negative inside the conduits and chambers; 1-Lipschitz.
    pub fn cave(&self, p: DVec3) -> f64 {
        self.caves.min_value(p, REACH, &self.context())
    }

    /// [`CarvedTerrain::cave`] by visiting every leaf, without the BVH: the reference the
    /// hierarchy's pruning is tested against.
    pub fn cave_without_bvh(&self, p: DVec3) -> f64 {
        self.caves.min_without_bvh(p, REACH, &self.context())
    }

    /// The water volume: negative in the water inside the conduits; 1-Lipschitz.
    pub fn water(&self, p: DVec3) -> f64 {
        let pieces = self.water.min_value(p, REACH, &self.context());
        pieces.max(self.cave(p))
    }

    /// The cave alone: the karst volume clipped to the rock under the terrain and inside the
    /// domain, negative inside the cave. Exact where its magnitude is below `reach`; elsewhere
    /// a value of the same sign and magnitude at least min(`reach`, the karst's 8 m cap), so
    /// that the search for the nearest conduit can stop early (the mesher asks for a cell or a
    /// half diagonal). Still 1-Lipschitz, so box pruning on it stays exact.
    pub fn cave_below_ground(&self, p: DVec3, reach: f64) -> f64 {
        let rock = self.uncarved(p);
        if rock >= reach {
            return rock;
        }
        self.caves.min_value(p, reach.min(REACH), &self.context()).max(rock)
    }

    /// A guaranteed lower bound of |f| over the box [lo, hi] (0 when the surface may cross it).
    pub fn bound(&self, lo: DVec3, hi: DVec3) -> f64 {
        let centre = (lo + hi) * 0.5;
        (self.eval(centre).abs() - (hi - lo).length() * 0.5).max(0.0)
    }

    /// Bytes held in memory by the evaluable tree: [karst leaves, their BVH and the sweep
    /// nodes and sections, water pieces and their BVH]. The model's own copy (kept for
    /// [`CarvedTerrain::model`]) is not counted.
    pub fn memory(&self) -> [usize; 2] {
        [self.caves.memory() + self.sweeps.memory(), self.water.memory()]
    }

    /// Number of karst leaves.
    pub fn leaves(&self) -> usize {
        self.caves.len()
    }
}

/// The karst leaves of `model`, their sweeps' nodes added to `sweeps`.
fn karst_leaves(model: &SdfModel, sweeps: &mut SweepTable) -> Vec<Leaf> {
    let mut leaves = Vec::new();
    leaves.extend(model.capsules.iter().map(|c| Leaf::Capsule(*c)));
    for s in &model.sweeps {
        leaves.push(Leaf::Sweep(sweeps.push(&s.sweep), s.kind));
    }
    for group in &model.spheres {
        leaves.extend(group.spheres.iter().map(|&s| Leaf::Sphere(s, group.kind)));
    }
    leaves.extend(model.chambers.iter().map(|c| Leaf::Chamber(Chamber::new(c))));
    leaves
}

fn water_leaves(model: &SdfModel, sweeps: &mut SweepTable) -> Vec<Leaf> {
    let piece = |w: &crate::model::WaterSpec| {
        let level = w.level.unwrap_or(f32::INFINITY);
        Leaf::Water(WaterLeaf { sweep: sweeps.push(&w.sweep), level })
    };
    model.water.iter().map(piece).collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::Capsule;
    use crate::terrain::TerrainField;
    use crate::testing::{Pairs, assert_lipschitz};
    use karst_geology::Domain;

    fn field() -> CarvedTerrain {
        CarvedTerrain::new(SdfModel {
            capsules: vec![Capsule { a: [20.0, 50.0, 20.0], b: [80.0, 50.0, 20.0], radius: 3.0 }],
            ..SdfModel::new(
                Domain { min: [0.0, 0.0, 0.0], max: [100.0, 100.0, 50.0] },
                TerrainField::Plane { elevation: 40.0, origin: [0.0, 0.0], gradient: [0.1, 0.0] },
            )
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
        assert_lipschitz(|p| f.eval(p), Pairs::new(7, 60.0, 4.0).around(DVec3::new(50.0, 50.0, 25.0)), 5000);
    }
}
