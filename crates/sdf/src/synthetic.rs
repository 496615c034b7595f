//! A synthetic conduit network of any size, for the whole-tree property tests and the
//! benchmarks (the looping preset of the skeleton stage is not available yet): random walks
//! with turning steps (tortuous, hence mostly unions of spheres) and straight runs (sweeps),
//! all conduit types, radii in [1, 3] m, phreatic below z = 60, one chamber every 16 conduits.

use glam::DVec3;
use karst_geology::Domain;
use karst_hydro::FlowUnits;
use karst_hydro::{ConduitWater, Hydro, SegmentWater, WaterType};
use karst_scene::rng::Random;
use karst_skeleton::{Conduit, ConduitType, Node, Skeleton, Zone};

/// The scene of the synthetic network: a 1 km × 1 km × 200 m block under a tilted plane.
pub const SCENE: &str = r#"
name = "synthetic"
seed = 11
[domain]
min = [0.0, 0.0, 0.0]
max = [1000.0, 1000.0, 200.0]
[terrain]
kind = "plane"
elevation = 190.0
origin = [0.0, 0.0]
gradient = [0.005, -0.004]
[[geology.water_tables]]
name = "wt"
elevation = 60.0
[[keypoints]]
name = "sink"
kind = "sink"
position = [100.0, 100.0, 180.0]
[[keypoints]]
name = "spring"
kind = "spring"
position = [900.0, 900.0, 60.0]
water_table = "wt"
"#;

/// `conduits` random conduits of `nodes` nodes each, with their flows.
pub fn network(seed: u64, conduits: usize, nodes: usize) -> (Skeleton, Hydro) {
    let mut random = Random::stream(seed, "sdf", "synthetic");
    let domain = Domain { min: [20.0, 20.0, 20.0], max: [980.0, 980.0, 170.0] };
    let mut skeleton =
        Skeleton { nodes: Vec::new(), conduits: Vec::new(), routes: Vec::new(), derived: Default::default() };
    let mut flows = Vec::new();
    let kinds = [
        ConduitType::Tube,
        ConduitType::Canyon,
        ConduitType::Keyhole,
        ConduitType::Passage,
        ConduitType::Bed,
    ];
    for c in 0..conduits {
        let mut p = DVec3::new(
            random.range(domain.min[0], domain.max[0]),
            random.range(domain.min[1], domain.max[1]),
            random.range(domain.min[2], domain.max[2]),
        );
        let tortuous = c % 2 == 0;
        let mut heading = random.range(0.0, std::f64::consts::TAU);
        let mut conduit = Conduit {
            nodes: Vec::new(),
            radius: Vec::new(),
            types: Vec::new(),
            phase: 0,
            keypoints: Vec::new(),
            profile: Vec::new(),
        };
        for i in 0..nodes {
            let zone = if p.z < 60.0 { Zone::Phreatic } else { Zone::Vadose };
            conduit.nodes.push(skeleton.nodes.len() as u32);
            skeleton.nodes.push(Node { position: p.to_array(), sample: 0, keypoint: None, zone });
            conduit.radius.push(random.range(1.0, 3.0));
            if i + 1 < nodes {
                let kind = if c % 16 == 15 && i == 0 {
                    ConduitType::Chamber
                } else {
                    kinds[random.index(kinds.len())]
                };
                conduit.types.push(kind);
                if tortuous {
                    heading += random.range(-1.2, 1.2);
                }
                let step = DVec3::new(heading.cos(), heading.sin(), random.range(-0.15, 0.15)) * 12.0;
                p = (p + step).clamp(DVec3::from_array(domain.min), DVec3::from_array(domain.max));
                if p.distance(DVec3::from_array(skeleton.nodes.last().expect("just pushed").position)) < 1.0 {
                    p += DVec3::new(0.0, 0.0, 2.0);
                }
            }
        }
        let dry = c % 5 == 4;
        let flow = if dry { 0.0 } else { random.range(0.1, 4.0) };
        let segments = conduit.nodes.windows(2).map(|w| segment_water(&skeleton, w, flow)).collect();
        skeleton.conduits.push(conduit);
        flows.push(ConduitWater { flow, downstream: true, dry, radius: None, segments });
    }
    let hydro = Hydro {
        flow_units: FlowUnits { min: 0.1, max: 4.0 },
        conduits: flows,
        nodes: Vec::new(),
        sinks: Vec::new(),
        springs: Vec::new(),
    };
    (skeleton, hydro)
}

/// Water of a synthetic segment: dry, flooded in the phreatic zone, else a stream as deep as
/// a tenth of its flow.
fn segment_water(skeleton: &Skeleton, ends: &[u32], flow: f64) -> SegmentWater {
    let phreatic = ends.iter().all(|&n| skeleton.nodes[n as usize].zone == Zone::Phreatic);
    let water = match (flow > 0.0, phreatic) {
        (false, _) => WaterType::Dry,
        (true, true) => WaterType::Sump,
        (true, false) => WaterType::Stream,
    };
    SegmentWater {
        downstream: true,
        flow,
        discharge: flow,
        water,
        slope: 0.0,
        flow_units: 0.0,
        look: None,
        speed: 0.0,
        depth: 0.1 * flow,
        width: 0.0,
        level: None,
        fall: None,
    }
}

/// The evaluation benchmark's points, from a fixed seed: `count` uniform in the domain of
/// `field`, and `count` within 6 m (per axis) of the nodes of `skeleton`, where the tree is
/// intricate. Shared by `cargo xtask bench` and the `evalbench` example, so that both time the
/// same points.
pub fn eval_points(field: &crate::CarvedTerrain, skeleton: &Skeleton, count: usize) -> [Vec<DVec3>; 2] {
    let mut state = 12345u64;
    let mut unit = move || {
        state = state.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
        (state >> 11) as f64 / (1u64 << 53) as f64
    };
    let d = &field.model().domain;
    let (lo, hi) = (DVec3::from_array(d.min), DVec3::from_array(d.max));
    let uniform: Vec<DVec3> =
        (0..count).map(|_| lo + (hi - lo) * DVec3::new(unit(), unit(), unit())).collect();
    let anchors: Vec<DVec3> = skeleton.nodes.iter().map(|n| DVec3::from_array(n.position)).collect();
    let near: Vec<DVec3> = (0..count)
        .map(|_| {
            let a = anchors[(unit() * anchors.len() as f64) as usize % anchors.len()];
            a + (DVec3::new(unit(), unit(), unit()) - 0.5) * 12.0
        })
        .collect();
    [uniform, near]
}
