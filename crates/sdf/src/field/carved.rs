//! Evaluating the construction tree of an [`SdfModel`]:
//!
//! - rock(p) = max(terrain(p), domain(p)), negative in the bedrock before karstification;
//! - cave(p) = min(REACH, min over the karst leaves (sweeps, spheres, chambers, capsules)),
//!   negative in the karst volume K;
//! - eval(p) = −smooth_union(−rock(p), cave(p), blend): the terrain minus K, rounded by `blend`
//!   where conduits open to the surface; negative in rock, positive in air;
//! - water(p) = max(min(REACH, min over water pieces), cave(p), rock(p)): negative in the
//!   water, which stays inside K and, like the cave mesh, inside the domain and under the
//!   ground (a spring on the domain's side would otherwise leave the water surface open there).
//!
//! All are 1-Lipschitz (see [`crate::tree::ops`]). The union over leaves runs through the BVH and only
//! needs the leaves that can go below −rock + blend; everything else cannot change eval.

use glam::DVec3;

use crate::SdfModel;
use crate::detail::rock::RockField;
use crate::field::bvh::{Bvh, Candidate};
use crate::field::primitive::{Context, Leaf, WaterLeaf};
use crate::payload::detail_factor;
use crate::tree::chamber::Chamber;
use crate::tree::ops;
use crate::tree::ops::REACH;
use crate::tree::sweep::{SweepSpec, SweepTable};
use crate::water::surface::SurfaceField;
use karst_skeleton::ConduitType;

/// The leaves that can matter within a box: see [`CarvedTerrain::near`].
#[derive(Debug, Clone, Default)]
pub struct Near {
    reach: f64,
    /// The leaf nodes farther than this from the box were left out.
    margin: f64,
    caves: Vec<Candidate>,
    water: Vec<Candidate>,
}

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
    /// The detail noise's gradient bound, likewise.
    detail_gradient: f64,
    /// The streams' riverbeds, basins, overhangs and water.
    surface: SurfaceField,
    /// The rough-wall relief's gradient bound (`full` passage detail; 0 without).
    relief_gradient: f64,
    /// Speleothems and breakdown blocks, taken out of the karst (`full` passage detail).
    rock_pieces: RockField,
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
        let detail_gradient = model.detail_noise.gradient_bound();
        let relief_gradient = model.full.relief().map_or(0.0, |r| r.noise.gradient_bound());
        let (m, gradient) = (&model, detail_gradient);
        let ctx =
            Context::new(&m.detail_noise, gradient, &m.chamber_noise, m.chamber_bias, &sweeps, &amplitude)
                .with_relief(m.full.relief(), relief_gradient);
        let caves = Bvh::build(karst, &ctx);
        let water = Bvh::build(water, &ctx);
        let terrain_scale = model.terrain.scale();
        let surface = SurfaceField::new(&model.surface);
        let rock_pieces = RockField::new(model.full.pieces());
        CarvedTerrain {
            model,
            caves,
            water,
            sweeps,
            amplitude,
            terrain_scale,
            detail_gradient,
            surface,
            relief_gradient,
            rock_pieces,
        }
    }

    pub fn model(&self) -> &SdfModel {
        &self.model
    }

    fn context(&self) -> Context<'_> {
        let m = &self.model;
        Context::new(
            &m.detail_noise,
            self.detail_gradient,
            &m.chamber_noise,
            m.chamber_bias,
            &self.sweeps,
            &self.amplitude,
        )
        .with_relief(m.full.relief(), self.relief_gradient)
    }

    /// min(limit, the karst leaves) (any value ≥ limit when the karst is), less the rock
    /// pieces put back into it: the karst volume K of every evaluation.
    fn karst(&self, p: DVec3, limit: f64) -> f64 {
        self.rock_pieces.carve(self.caves.min_value(p, limit, &self.context()), p)
    }

    /// [`CarvedTerrain::karst`] over the leaf nodes of `near` only.
    fn karst_among(&self, near: &Near, p: DVec3, limit: f64) -> f64 {
        self.rock_pieces.carve(self.caves.min_value_among(&near.caves, p, limit, &self.context()), p)
    }

    /// Rock before the caves: below the terrain and inside the domain, less the riverbeds,
    /// basins and overhangs of the surface water (negative inside).
    pub fn rock(&self, p: DVec3) -> f64 {
        let terrain = (p.z - self.model.terrain.height(p.x, p.y)) * self.terrain_scale;
        let rock = terrain.max(self.model.domain.signed_distance(p));
        if self.surface.is_empty() { rock } else { rock.max(-self.surface.carve(p)) }
    }

    /// The surface water, in the air of the carved terrain and inside the domain (negative
    /// inside): like the cave, it is closed where a river leaves the domain.
    fn surface_water(&self, p: DVec3) -> f64 {
        self.surface.water(p).max(-self.rock(p)).max(self.model.domain.signed_distance(p))
    }

    /// f(p): negative in rock, positive in air; 1-Lipschitz.
    pub fn eval(&self, p: DVec3) -> f64 {
        let rock = self.rock(p);
        let blend = self.model.blend;
        // The smooth union equals −rock wherever the caves stay above −rock + blend.
        let caves = self.karst(p, (-rock + blend).min(REACH));
        -ops::smooth_union(-rock, caves, blend)
    }

    /// [`CarvedTerrain::eval`] where |f(p)| < `reach`; elsewhere a value of the same sign and
    /// magnitude at least `reach`. The search for the nearest conduit stops at `reach` + blend
    /// instead of the depth below the ground, so that a point deep in the rock (the domain's
    /// floor lies hundreds of metres down) costs a search of a few metres.
    ///
    /// Why it is enough: eval ≥ rock always (the smooth union is below −rock), so rock ≥ reach
    /// settles the sign and the magnitude. Otherwise the caves are searched up to
    /// L = min(−rock + blend, REACH, reach + blend). When the nearest cave value is below L it is
    /// exact and so is the result. When it is at least L = −rock + blend the smooth union is
    /// −rock, exact as in `eval`. When it is at least L = reach + blend < −rock + blend, both
    /// operands of the smooth union are at least reach and the one at reach + d (d ≥ 0) lies
    /// within the blend of the other by at most blend − d: the union is at least
    /// reach + d − d²/(4 blend) ≥ reach whether the true or the clamped value is used, so both
    /// results are ≤ −reach.
    pub fn eval_within(&self, p: DVec3, reach: f64) -> f64 {
        self.carved(p, reach, |limit| self.karst(p, limit))
    }

    /// [`CarvedTerrain::eval_within`] for a point of the box `near` was gathered for, with a
    /// reach at most its reach: the same value, bit for bit, without walking the hierarchy.
    pub fn eval_near(&self, near: &Near, p: DVec3, reach: f64) -> f64 {
        debug_assert!(reach <= near.reach);
        self.carved(p, reach, |limit| self.karst_among(near, p, limit))
    }

    fn carved(&self, p: DVec3, reach: f64, caves: impl FnOnce(f64) -> f64) -> f64 {
        let rock = self.rock(p);
        if rock >= reach {
            return rock;
        }
        let blend = self.model.blend;
        let caves = caves((-rock + blend).min(REACH).min(reach + blend));
        -ops::smooth_union(-rock, caves, blend)
    }

    /// The karst leaves that can matter for [`CarvedTerrain::eval_near`] at points of the box
    /// [lo, hi] with a reach at most `reach`.
    pub fn near(&self, lo: DVec3, hi: DVec3, reach: f64) -> Near {
        self.gather(lo, hi, reach, reach.min(REACH) + self.model.blend.max(0.0), false)
    }

    /// The karst leaves that can matter for [`CarvedTerrain::cave_below_ground_near`] at points
    /// of the box [lo, hi] with a reach at most `reach` (no blend: a smaller margin than
    /// [`CarvedTerrain::near`]).
    pub fn near_cave(&self, lo: DVec3, hi: DVec3, reach: f64) -> Near {
        self.gather(lo, hi, reach, reach.min(REACH), false)
    }

    /// The leaves (karst and water) that can matter for [`CarvedTerrain::water_near`] at points
    /// of the box [lo, hi] with a reach at most `reach`.
    pub fn near_water(&self, lo: DVec3, hi: DVec3, reach: f64) -> Near {
        self.gather(lo, hi, reach, reach.min(REACH), true)
    }

    fn gather(&self, lo: DVec3, hi: DVec3, reach: f64, margin: f64, water: bool) -> Near {
        let mut near = Near { reach, margin, caves: Vec::new(), water: Vec::new() };
        self.caves.near_box(lo, hi, margin, &mut near.caves);
        if water {
            self.water.near_box(lo, hi, margin, &mut near.water);
        }
        near
    }

    /// Whether the caves or the surface water may carve the rock within `margin` of the box
    /// [lo, hi]: a leaf node of the karst or the horizontal box of a riverbed, basin or
    /// overhang comes that close (the blend of cave entrances added). False means that the
    /// rock there is the plain terrain: the mesher meshes it coarsely.
    pub fn may_carve(&self, lo: DVec3, hi: DVec3, margin: f64) -> bool {
        let mut caves = Vec::new();
        self.caves.near_box(lo, hi, margin + self.model.blend.max(0.0), &mut caves);
        !caves.is_empty() || self.surface.carves_within(lo.truncate(), hi.truncate(), margin)
    }

    /// Whether the caves or the surface water carve the rock within `margin` of the box
    /// [lo, hi], judged from the karst's value at its centre (exact up to the karst's cap, so
    /// a box whose half diagonal and margin pass the cap is always said carved) and the surface
    /// pieces' horizontal boxes: a finer test than [`CarvedTerrain::may_carve`] for small boxes.
    pub fn carves(&self, lo: DVec3, hi: DVec3, margin: f64) -> bool {
        let within = (hi - lo).length() * 0.5 + margin + self.model.blend.max(0.0);
        self.cave((lo + hi) * 0.5) < within.min(REACH)
            || within >= REACH
            || self.surface.carves_within(lo.truncate(), hi.truncate(), margin)
    }

    /// A lower bound of the cave alone (`cave_below_ground` with no reach) over the box
    /// [lo, hi], inside the box `near` was gathered for: the gap from the box to
    /// the nearest karst leaf node, at most the gathering margin and REACH. The cave is at
    /// least the karst, whose leaves are at least their boxes' distance, so a positive floor
    /// proves the box free of caves however large it is; the value at its centre cannot, the
    /// karst being clamped at REACH (the mesher's octree would split all the rock far from the
    /// conduits down to boxes of half diagonal below REACH).
    pub fn cave_floor(&self, near: &Near, lo: DVec3, hi: DVec3) -> f64 {
        Bvh::gap_among(&near.caves, lo, hi, near.margin.min(REACH))
    }

    /// A lower bound of the water ([`CarvedTerrain::water`]) over the box [lo, hi], as
    /// [`CarvedTerrain::cave_floor`]: the water in the conduits is at least the cave and at least
    /// its pieces (at least their leaf nodes' gaps), and the surface water, where the scene has
    /// some, at least its value at the box's centre less the half diagonal (1-Lipschitz).
    pub fn water_floor(&self, near: &Near, lo: DVec3, hi: DVec3) -> f64 {
        let pieces = Bvh::gap_among(&near.water, lo, hi, near.margin.min(REACH));
        let under = self.cave_floor(near, lo, hi).max(pieces);
        if self.surface.is_empty() || under <= 0.0 {
            return under;
        }
        under.min(self.surface_water((lo + hi) * 0.5) - (hi - lo).length() * 0.5)
    }

    /// The karst volume alone: negative inside the conduits and chambers; 1-Lipschitz.
    pub fn cave(&self, p: DVec3) -> f64 {
        self.karst(p, REACH)
    }

    /// [`CarvedTerrain::cave`] by visiting every leaf, without the BVH: the reference the
    /// hierarchy's pruning is tested against.
    pub fn cave_without_bvh(&self, p: DVec3) -> f64 {
        self.rock_pieces.carve(self.caves.min_without_bvh(p, REACH, &self.context()), p)
    }

    /// The water volume: negative in the water inside the conduits, under the ground and in the
    /// domain; 1-Lipschitz.
    pub fn water(&self, p: DVec3) -> f64 {
        self.water_within(p, f64::INFINITY)
    }

    /// The cave alone: the karst volume clipped to the rock under the terrain and inside the
    /// domain, negative inside the cave. Exact where its magnitude is below `reach`; elsewhere
    /// a value of the same sign and magnitude at least min(`reach`, the karst's 8 m cap), so
    /// that the search for the nearest conduit can stop early (the mesher asks for a cell or a
    /// half diagonal). Still 1-Lipschitz, so box pruning on it stays exact.
    pub fn cave_below_ground(&self, p: DVec3, reach: f64) -> f64 {
        let rock = self.rock(p);
        if rock >= reach {
            return rock;
        }
        self.karst(p, reach.min(REACH)).max(rock)
    }

    /// [`CarvedTerrain::cave_below_ground`] for a point of the box `near` was gathered for.
    pub fn cave_below_ground_near(&self, near: &Near, p: DVec3, reach: f64) -> f64 {
        debug_assert!(reach <= near.reach);
        let rock = self.rock(p);
        if rock >= reach {
            return rock;
        }
        self.karst_among(near, p, reach.min(REACH)).max(rock)
    }

    /// [`CarvedTerrain::water`] where |w(p)| < `reach`; elsewhere a value of the same sign and
    /// magnitude at least min(`reach`, REACH). The water lies inside the cave, so where the cave
    /// alone is already at least `reach` away (deep in rock) the water pieces are not searched.
    pub fn water_within(&self, p: DVec3, reach: f64) -> f64 {
        let cave = self.cave_below_ground(p, reach);
        let under = if cave >= reach {
            cave
        } else {
            self.water.min_value(p, reach.min(REACH), &self.context()).max(cave)
        };
        if self.surface.is_empty() { under } else { under.min(self.surface_water(p)) }
    }

    /// [`CarvedTerrain::water_within`] for a point of the box `near` (from
    /// [`CarvedTerrain::near_water`]) was gathered for.
    pub fn water_near(&self, near: &Near, p: DVec3, reach: f64) -> f64 {
        let cave = self.cave_below_ground_near(near, p, reach);
        let under = if cave >= reach {
            cave
        } else {
            self.water.min_value_among(&near.water, p, reach.min(REACH), &self.context()).max(cave)
        };
        if self.surface.is_empty() { under } else { under.min(self.surface_water(p)) }
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
        [self.caves.memory() + self.sweeps.memory() + self.rock_pieces.memory(), self.water.memory()]
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
    for run in model.sweep_runs() {
        let pieces: Vec<SweepSpec> = run.iter().map(|s| s.sweep).collect();
        leaves.push(Leaf::Sweep(sweeps.push_run(&pieces), run[0].kind));
    }
    for group in &model.spheres {
        leaves.extend(group.spheres.iter().map(|&s| Leaf::Sphere(s, group.kind)));
    }
    leaves.extend(model.chambers.iter().map(|c| Leaf::Chamber(Chamber::new(c))));
    leaves
}

fn water_leaves(model: &SdfModel, sweeps: &mut SweepTable) -> Vec<Leaf> {
    let piece = |w: &crate::payload::WaterSpec| {
        let level = w.level.unwrap_or(f32::INFINITY);
        Leaf::Water(WaterLeaf { sweep: sweeps.push(&w.sweep), level })
    };
    model.water.iter().map(piece).collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::Capsule;
    use crate::testing::{Pairs, assert_lipschitz};
    use crate::tree::terrain::TerrainField;
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
    fn eval_within_is_exact_near_the_surface_and_keeps_sign_and_reach_elsewhere() {
        // A shaft through the ground, so that the blend where it opens matters.
        let mut model = field().model().clone();
        model.blend = 1.5;
        model.capsules.push(Capsule { a: [50.0, 80.0, 20.0], b: [50.0, 80.0, 60.0], radius: 2.0 });
        let f = CarvedTerrain::new(model);
        let mut random = karst_scene::rng::Random::stream(3, "sdf", "eval_within");
        for _ in 0..20_000 {
            let p =
                DVec3::new(random.range(-5.0, 105.0), random.range(-5.0, 105.0), random.range(-5.0, 55.0));
            let exact = f.eval(p);
            for reach in [0.3, 1.0, 2.0, 5.0, 50.0] {
                let v = f.eval_within(p, reach);
                if exact.abs() < reach {
                    assert_eq!(v, exact, "{p} reach {reach}");
                } else {
                    assert!(v.signum() == exact.signum() && v.abs() >= reach, "{p} {reach}: {v} vs {exact}");
                }
            }
        }
    }

    #[test]
    fn gathered_leaves_give_the_same_bits_as_the_hierarchy() {
        let mut model = field().model().clone();
        model.blend = 1.0;
        for i in 0..40 {
            let x = 10.0 + i as f64 * 2.0;
            model.capsules.push(Capsule {
                a: [x, 30.0, 15.0],
                b: [x + 3.0, 70.0, 30.0 + i as f64],
                radius: 1.5,
            });
        }
        let f = CarvedTerrain::new(model);
        let mut random = karst_scene::rng::Random::stream(4, "sdf", "near");
        for _ in 0..300 {
            let lo = DVec3::new(random.range(0.0, 95.0), random.range(0.0, 95.0), random.range(0.0, 45.0));
            let hi = lo + DVec3::splat(random.range(0.5, 5.0));
            let reach = random.range(0.2, 10.0);
            let (near, near_cave) = (f.near(lo, hi, reach), f.near_cave(lo, hi, reach));
            let near_water = f.near_water(lo, hi, reach);
            for _ in 0..20 {
                let p = lo
                    + (hi - lo)
                        * DVec3::new(random.range(0.0, 1.0), random.range(0.0, 1.0), random.range(0.0, 1.0));
                let r = reach * random.range(0.5, 1.0);
                assert_eq!(f.eval_near(&near, p, r).to_bits(), f.eval_within(p, r).to_bits());
                assert_eq!(
                    f.cave_below_ground_near(&near_cave, p, r).to_bits(),
                    f.cave_below_ground(p, r).to_bits()
                );
                assert_eq!(f.water_near(&near_water, p, r).to_bits(), f.water_within(p, r).to_bits());
            }
        }
    }

    #[test]
    fn is_one_lipschitz() {
        let f = field();
        assert_lipschitz(|p| f.eval(p), Pairs::new(7, 60.0, 4.0).around(DVec3::new(50.0, 50.0, 25.0)), 5000);
    }
}
