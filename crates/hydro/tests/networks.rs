//! Flow on random networks (seeded): conservation at every node, springs' discharge equal to
//! the water of the sinks that reach them, consistent orientation on loops; the errors of bad
//! networks; the CSV export read back.

use std::collections::BTreeMap;

use karst_hydro::{Hydro, HydroError, Inputs, WaterType, compute, export};
use karst_scene::params::{HydroParams, PoolOutlet, PoolWeights};
use karst_scene::rng::Random;
use karst_skeleton::{Conduit, ConduitType, Node, Route, Skeleton, Zone};
use karst_stage::{Blame, Failure};

fn node(p: [f64; 3], zone: Zone) -> Node {
    Node { position: p, sample: 0, keypoint: None, zone }
}

fn conduit(nodes: Vec<u32>) -> Conduit {
    let n = nodes.len();
    Conduit {
        nodes,
        radius: vec![1.5; n],
        types: vec![ConduitType::Canyon; n - 1],
        phase: 0,
        keypoints: vec![],
        profile: Vec::new(),
    }
}

fn route(sink: &str, spring: &str, weight: f64, a: u32, b: u32) -> Route {
    Route { sink: sink.into(), spring: spring.into(), weight, nodes: vec![a, b], cost: 0.0 }
}

/// A random network: a random spanning tree plus extra links (loops), some links cut in two
/// by an interior node, a detached dead-end piece, 1–3 springs and 1–6 sinks; nodes below
/// z = 30 are phreatic.
fn random_network(seed: u64) -> Skeleton {
    let mut rng = Random::stream(seed, "hydro-test", "network");
    let n = 8 + rng.index(40);
    let mut nodes: Vec<Node> = (0..n)
        .map(|_| {
            let p = [rng.range(0.0, 500.0), rng.range(0.0, 500.0), rng.range(0.0, 200.0)];
            node(p, if p[2] < 30.0 { Zone::Phreatic } else { Zone::Vadose })
        })
        .collect();
    let mut pairs: Vec<(u32, u32)> = (1..n).map(|i| (rng.index(i) as u32, i as u32)).collect();
    for _ in 0..rng.index(n) {
        let (a, b) = (rng.index(n) as u32, rng.index(n) as u32);
        if a != b && !pairs.iter().any(|&(x, y)| (x, y) == (a, b) || (x, y) == (b, a)) {
            pairs.push((a, b));
        }
    }
    let mut conduits = Vec::new();
    for (a, b) in pairs {
        if rng.uniform() < 0.3 {
            let [pa, pb] = [a, b].map(|i| nodes[i as usize].position);
            let mid = [0.5 * (pa[0] + pb[0]), 0.5 * (pa[1] + pb[1]), rng.range(0.0, 200.0)];
            nodes.push(node(mid, if mid[2] < 30.0 { Zone::Phreatic } else { Zone::Vadose }));
            conduits.push(conduit(vec![a, nodes.len() as u32 - 1, b]));
        } else {
            conduits.push(conduit(vec![a, b]));
        }
    }
    let detached = nodes.len() as u32;
    nodes.push(node([600.0, 0.0, 100.0], Zone::Vadose));
    nodes.push(node([650.0, 0.0, 90.0], Zone::Vadose));
    conduits.push(conduit(vec![detached, detached + 1]));
    let springs: Vec<u32> = (0..1 + rng.index(3)).map(|_| rng.index(n) as u32).collect();
    let routes = (0..1 + rng.index(6))
        .map(|s| {
            let spring = rng.index(springs.len());
            let weight = if rng.uniform() < 0.1 { 0.0 } else { rng.range(0.1, 10.0) };
            route(
                &format!("sink-{s}"),
                &format!("spring-{spring}"),
                weight,
                rng.index(n) as u32,
                springs[spring],
            )
        })
        .collect();
    Skeleton { nodes, conduits, routes, derived: Default::default() }
}

/// Water in minus water out at every node, recharge and discharge included, and the water in.
fn balance(s: &Skeleton, h: &Hydro) -> Vec<(f64, f64)> {
    let mut b = vec![(0.0, 0.0); s.nodes.len()];
    for (c, w) in s.conduits.iter().zip(&h.conduits) {
        for (pair, seg) in c.nodes.windows(2).zip(&w.segments) {
            let (from, to) = if seg.downstream { (pair[0], pair[1]) } else { (pair[1], pair[0]) };
            b[from as usize].0 -= seg.flow;
            b[to as usize].0 += seg.flow;
            b[to as usize].1 += seg.flow;
        }
    }
    for sink in &h.sinks {
        b[sink.node as usize].0 += sink.recharge;
        b[sink.node as usize].1 += sink.recharge;
    }
    for spring in &h.springs {
        b[spring.node as usize].0 -= spring.flow;
    }
    b
}

/// True when the wet links, directed downstream, have no cycle (Kahn's algorithm).
fn acyclic(s: &Skeleton, h: &Hydro) -> bool {
    let mut out: Vec<Vec<u32>> = vec![Vec::new(); s.nodes.len()];
    let mut indegree = vec![0usize; s.nodes.len()];
    for (c, w) in s.conduits.iter().zip(&h.conduits) {
        for (pair, seg) in c.nodes.windows(2).zip(&w.segments).filter(|(_, seg)| seg.flow > 0.0) {
            let (from, to) = if seg.downstream { (pair[0], pair[1]) } else { (pair[1], pair[0]) };
            out[from as usize].push(to);
            indegree[to as usize] += 1;
        }
    }
    let mut ready: Vec<usize> = (0..s.nodes.len()).filter(|&i| indegree[i] == 0).collect();
    let mut seen = 0;
    while let Some(i) = ready.pop() {
        seen += 1;
        for &j in &out[i] {
            indegree[j as usize] -= 1;
            if indegree[j as usize] == 0 {
                ready.push(j as usize);
            }
        }
    }
    seen == s.nodes.len()
}

#[test]
fn flow_is_conserved_on_random_networks_and_springs_return_the_sinks_water() {
    let mut checked = 0;
    for seed in 0..300 {
        let skeleton = random_network(seed);
        let h = match compute(&skeleton, &HydroParams::default(), &Inputs::default()) {
            Ok(h) => h,
            // A sink may sit where no conduit leads down to a spring: that is an input error.
            Err(HydroError::NoDownstreamPath { .. }) => continue,
            Err(e) => panic!("seed {seed}: {e}"),
        };
        checked += 1;
        for (i, (imbalance, inflow)) in balance(&skeleton, &h).into_iter().enumerate() {
            assert!(
                imbalance.abs() <= 1e-9 * inflow.max(f64::MIN_POSITIVE),
                "seed {seed}, node {i}: {imbalance} of {inflow}"
            );
        }
        assert!(acyclic(&skeleton, &h), "seed {seed}: the orientation has a cycle");
        // Every spring gives out exactly the water of the sinks reaching it ...
        let mut from_sinks: BTreeMap<&str, f64> = BTreeMap::new();
        for sink in &h.sinks {
            let total: f64 = sink.springs.iter().map(|s| s.flow).sum();
            assert!(
                (total - sink.recharge).abs() <= 1e-9 * sink.recharge.max(1.0),
                "seed {seed}: {}",
                sink.name
            );
            for share in &sink.springs {
                *from_sinks.entry(&share.name).or_default() += share.flow;
            }
        }
        for spring in &h.springs {
            let expected = from_sinks.get(spring.name.as_str()).copied().unwrap_or(0.0);
            assert!(
                (spring.flow - expected).abs() <= 1e-9 * expected.max(1.0),
                "seed {seed}: {}",
                spring.name
            );
            // ... which is all their recharge for sinks whose water reaches no other spring.
            let whole: f64 = h
                .sinks
                .iter()
                .filter(|s| s.springs.len() == 1 && s.springs[0].name == spring.name)
                .map(|s| s.recharge)
                .sum();
            assert!(spring.flow + 1e-9 >= whole, "seed {seed}: {}", spring.name);
        }
        // The detached piece carries no water and every wet vadose segment has a water type.
        assert!(h.conduits.last().unwrap().dry);
        for (c, w) in skeleton.conduits.iter().zip(&h.conduits) {
            for (pair, seg) in c.nodes.windows(2).zip(&w.segments) {
                let vadose = pair.iter().any(|&n| skeleton.nodes[n as usize].zone == Zone::Vadose);
                assert_eq!(seg.flow > 0.0, seg.water != WaterType::Dry, "seed {seed}");
                if seg.flow > 0.0 && vadose {
                    assert!(seg.water != WaterType::Sump, "seed {seed}");
                }
            }
        }
    }
    assert!(checked > 150, "only {checked} networks had every sink drained");
}

/// Sink a at node 0 (z 100) over a T: 0 → 1, then 1 → 2 (straight on) and 1 → 3 (sideways),
/// 2 and 3 both springs.
fn tee() -> Skeleton {
    let nodes = vec![
        node([0.0, 0.0, 100.0], Zone::Vadose),
        node([100.0, 0.0, 90.0], Zone::Vadose),
        node([200.0, 0.0, 80.0], Zone::Vadose),
        node([100.0, 100.0, 80.0], Zone::Vadose),
    ];
    Skeleton {
        nodes,
        conduits: vec![conduit(vec![0, 1]), conduit(vec![1, 2]), conduit(vec![3, 1])],
        routes: vec![route("a", "east", 4.0, 0, 2), route("a", "north", 4.0, 0, 3)],
        derived: Default::default(),
    }
}

#[test]
fn water_mostly_keeps_its_course_at_a_branch() {
    let h = compute(&tee(), &HydroParams::default(), &Inputs::default()).unwrap();
    let (straight, side) = (&h.conduits[1].segments[0], &h.conduits[2].segments[0]);
    assert!(straight.downstream && !side.downstream);
    assert!(straight.flow > side.flow && side.flow > 0.0, "{} {}", straight.flow, side.flow);
    assert!((straight.flow + side.flow - 4.0).abs() < 1e-12);
    // A chamber at the branch splits equally.
    let mut pool = tee();
    pool.conduits[0].types = vec![ConduitType::Chamber];
    let h = compute(&pool, &HydroParams::default(), &Inputs::default()).unwrap();
    assert_eq!(h.conduits[1].segments[0].flow, 2.0);
    assert_eq!(h.conduits[2].segments[0].flow, 2.0);
}

fn outlet(towards: [f64; 3], weight: f64) -> PoolOutlet {
    PoolOutlet { towards, weight }
}

fn pools(pools: Vec<PoolWeights>) -> HydroParams {
    HydroParams { pools, ..HydroParams::default() }
}

#[test]
fn a_pool_shares_its_water_by_the_user_weights_of_its_outlets() {
    let mut pool = tee();
    pool.conduits[0].types = vec![ConduitType::Chamber];
    // The outlet towards the east gets 3, the one towards the north 1 (points past the ends).
    let weights = PoolWeights {
        at: [101.0, 1.0, 91.0],
        radius: 5.0,
        outlets: vec![outlet([500.0, 10.0, 0.0], 3.0), outlet([90.0, 400.0, 0.0], 1.0)],
    };
    let h = compute(&pool, &pools(vec![weights.clone()]), &Inputs::default()).unwrap();
    assert_eq!(h.conduits[1].segments[0].flow, 3.0);
    assert_eq!(h.conduits[2].segments[0].flow, 1.0);
    let east = h.springs.iter().find(|s| s.name == "east").unwrap();
    assert_eq!(east.flow, 3.0);
    // A zero weight closes an outlet; all water takes the other.
    let mut closed = weights.clone();
    closed.outlets[1].weight = 0.0;
    let h = compute(&pool, &pools(vec![closed]), &Inputs::default()).unwrap();
    assert_eq!((h.conduits[1].segments[0].flow, h.conduits[2].segments[0].flow), (4.0, 0.0));
    // Without the chamber node 1 is no pool: the entry names itself and the nearest pool.
    let e = compute(&tee(), &pools(vec![weights.clone()]), &Inputs::default()).unwrap_err();
    assert_eq!(e.blame(), Blame::Scene);
    assert!(e.to_string().starts_with("hydro.pools[0]: no pool within 5 m of [101.0, 1.0, 91.0] ("), "{e}");
    // Two entries for one pool, and a pool whose every outgoing conduit gets 0.
    let e = compute(&pool, &pools(vec![weights.clone(), weights.clone()]), &Inputs::default()).unwrap_err();
    assert_eq!(e, HydroError::SamePool { first: 0, second: 1, node: 1 });
    let shut = PoolWeights {
        outlets: vec![outlet([500.0, 10.0, 0.0], 0.0), outlet([-500.0, -500.0, 90.0], 2.0)],
        ..weights
    };
    let e = compute(&pool, &pools(vec![shut]), &Inputs::default()).unwrap_err();
    assert_eq!(e, HydroError::PoolClosed { index: 0, node: 1 });
    assert!(e.to_string().contains("every outgoing conduit of pool node 1 gets weight 0"), "{e}");
}

#[test]
fn flow_is_conserved_with_user_weights_at_pools() {
    let mut checked = 0;
    for seed in 0..300 {
        let mut skeleton = random_network(seed);
        let mut rng = Random::stream(seed, "hydro-test", "pools");
        for c in &mut skeleton.conduits {
            for t in &mut c.types {
                if rng.uniform() < 0.25 {
                    *t = ConduitType::Chamber;
                }
            }
        }
        // Weights at every chamber end, 1–3 outlets in random directions, some weights 0.
        let mut at: Vec<u32> = skeleton
            .conduits
            .iter()
            .flat_map(|c| {
                c.types
                    .iter()
                    .enumerate()
                    .filter(|(_, t)| **t == ConduitType::Chamber)
                    .flat_map(|(i, _)| [c.nodes[i], c.nodes[i + 1]])
            })
            .collect();
        at.sort_unstable();
        at.dedup();
        let entries: Vec<PoolWeights> = at
            .iter()
            .map(|&n| {
                let p = skeleton.nodes[n as usize].position;
                let outlets = (0..1 + rng.index(3))
                    .map(|o| {
                        let towards =
                            [p[0] + rng.range(-100.0, 100.0), p[1] + rng.range(-100.0, 100.0), p[2] - 50.0];
                        outlet(towards, if o > 0 && rng.uniform() < 0.2 { 0.0 } else { rng.range(0.1, 5.0) })
                    })
                    .collect();
                PoolWeights { at: p, radius: 1e-6, outlets }
            })
            .collect();
        let h = match compute(&skeleton, &pools(entries), &Inputs::default()) {
            Ok(h) => h,
            Err(HydroError::NoDownstreamPath { .. } | HydroError::PoolClosed { .. }) => continue,
            Err(e) => panic!("seed {seed}: {e}"),
        };
        checked += 1;
        for (i, (imbalance, inflow)) in balance(&skeleton, &h).into_iter().enumerate() {
            assert!(
                imbalance.abs() <= 1e-9 * inflow.max(f64::MIN_POSITIVE),
                "seed {seed}, node {i}: {imbalance} of {inflow}"
            );
        }
        let recharge: f64 = h.sinks.iter().map(|s| s.recharge).sum();
        let out: f64 = h.springs.iter().map(|s| s.flow).sum();
        assert!((recharge - out).abs() <= 1e-9 * recharge.max(1.0), "seed {seed}: {recharge} in, {out} out");
    }
    eprintln!("{checked} networks checked");
    assert!(checked > 80, "only {checked} networks were checked");
}

/// A sink at z 100, a short slope, a 55 m vertical shaft (nodes 1 → 2), then two phreatic
/// nodes down to the spring.
fn shaft_nodes() -> Vec<Node> {
    vec![
        node([0.0, 0.0, 100.0], Zone::Vadose),
        node([50.0, 0.0, 95.0], Zone::Vadose),
        node([50.0, 0.0, 40.0], Zone::Vadose),
        node([150.0, 0.0, 20.0], Zone::Phreatic),
        node([250.0, 0.0, 10.0], Zone::Phreatic),
    ]
}

#[test]
fn a_vertical_shaft_with_water_is_a_free_fall_with_its_parabola() {
    let skeleton = Skeleton {
        nodes: shaft_nodes(),
        conduits: vec![conduit(vec![0, 1, 2, 3, 4])],
        routes: vec![route("a", "s", 1.0, 0, 4)],
        derived: Default::default(),
    };
    let h = compute(&skeleton, &HydroParams::default(), &Inputs::default()).unwrap();
    let s = &h.conduits[0].segments;
    assert!(s[1].water.is_free_fall(), "{:?}", s[1].water);
    let fall = s[1].fall.as_ref().unwrap();
    assert_eq!(fall.drop, 55.0);
    assert_eq!(fall.direction, [1.0, 0.0]);
    assert!(fall.throw > 0.0 && s[1].level.is_none());
    assert!(!s[0].water.is_free_fall() && s[0].level.is_some());
    assert_eq!(s[3].water, WaterType::Sump);
}

#[test]
fn bad_networks_are_named() {
    let params = HydroParams::default();
    // A negative weight never reaches the stage: skeleton.json fails its validation.
    let mut negative = tee();
    negative.routes[0].weight = -2.0;
    let invalid = karst_artifact::Payload::validate(&negative).unwrap_err();
    assert_eq!(invalid.field, "routes[0].weight");

    let mut no_spring = tee();
    no_spring.routes.clear();
    assert_eq!(compute(&no_spring, &params, &Inputs::default()).unwrap_err(), HydroError::NoSpring);

    let mut cut = tee();
    cut.nodes.push(node([0.0, 500.0, 100.0], Zone::Vadose));
    cut.routes.push(route("lost", "east", 1.0, 4, 2));
    let e = compute(&cut, &params, &Inputs::default()).unwrap_err();
    assert!(e.to_string().contains("sink \"lost\" (node 4) has no downstream path"), "{e}");
}

#[test]
fn flow_sized_radii_grow_with_flow() {
    let params = HydroParams { flow_radius: Some([0.5, 4.0]), ..HydroParams::default() };
    let h = compute(&tee(), &params, &Inputs::default()).unwrap();
    let r = |c: usize| h.conduits[c].radius.as_ref().unwrap().clone();
    assert_eq!(r(0), vec![4.0, 4.0]);
    assert!(r(1)[1] > r(2)[0] && r(2)[0] >= 0.5);
}

#[test]
fn the_csv_export_loads_back_as_nodes_and_links() {
    let skeleton = random_network(3);
    let h = compute(&skeleton, &HydroParams::default(), &Inputs::default()).unwrap();
    let dir = karst_testkit::scratch("hydro-csv");
    export::write(&dir, &skeleton, &h).unwrap();
    let table = |name: &str| -> (Vec<String>, Vec<Vec<String>>) {
        let text = std::fs::read_to_string(dir.join(name)).unwrap();
        let mut lines = text.lines().map(|l| l.split(',').map(str::to_string).collect::<Vec<_>>());
        (lines.next().unwrap(), lines.collect())
    };
    let (header, nodes) = table(export::NODES);
    assert_eq!(header, ["id", "x", "y", "z", "kind", "diameter"]);
    assert_eq!(nodes.len(), skeleton.nodes.len());
    let inlets = nodes.iter().filter(|r| r[4] == "inlet").count();
    let mut sink_nodes: Vec<u32> =
        h.sinks.iter().map(|s| s.node).filter(|n| h.springs.iter().all(|w| w.node != *n)).collect();
    sink_nodes.sort();
    sink_nodes.dedup();
    assert_eq!(inlets, sink_nodes.len());
    assert!(nodes.iter().all(|r| r[4] == "inlet" || r[4] == "outlet" || r[4] == "junction"));
    let (header, links) = table(export::LINKS);
    assert_eq!(header, ["id", "from", "to", "length", "diameter", "flow"]);
    assert_eq!(links.len(), skeleton.links().len());
    // Discharge in m³/s is conserved too: what leaves the inlets reaches the outlets.
    let num = |s: &str| s.parse::<f64>().unwrap();
    let mut net = vec![0.0; nodes.len()];
    // Ids are 1-based, node i of the skeleton being id i + 1, as in every table karstgen writes.
    assert!(nodes.iter().enumerate().all(|(i, r)| r[0] == (i + 1).to_string()));
    for l in &links {
        let (from, to, q) = (num(&l[1]) as usize - 1, num(&l[2]) as usize - 1, num(&l[5]));
        assert!(num(&l[3]) >= 0.0 && num(&l[4]) > 0.0 && q >= 0.0);
        net[from] -= q;
        net[to] += q;
    }
    let outlets: f64 = nodes.iter().zip(&net).filter(|(r, _)| r[4] == "outlet").map(|(_, q)| q).sum();
    // (sinks sitting on a spring give their water out without a link.)
    let recharge: f64 = h.sinks.iter().map(|s| s.recharge).sum();
    let linked: f64 = h
        .sinks
        .iter()
        .filter(|s| !sink_nodes.is_empty() && sink_nodes.contains(&s.node))
        .map(|s| s.recharge)
        .sum();
    let expected = HydroParams::default().total_discharge * linked / recharge;
    assert!(expected > 0.0 && (outlets - expected).abs() < 1e-9, "{outlets} {expected}");
}

#[test]
fn the_picture_colours_every_segment_by_its_water_type() {
    use karst_hydro::{colour, picture};
    let mut nodes = shaft_nodes();
    nodes.push(node([50.0, 80.0, 60.0], Zone::Vadose));
    let skeleton = Skeleton {
        nodes,
        conduits: vec![conduit(vec![0, 1, 2, 3, 4]), conduit(vec![2, 5])],
        routes: vec![route("a", "s", 1.0, 0, 4)],
        derived: Default::default(),
    };
    let h = compute(&skeleton, &HydroParams::default(), &Inputs::default()).unwrap();
    let canvas = picture(&skeleton, &h);
    // The legend lists only the water types present, so the whole picture can be searched.
    let (width, height) = (i64::from(canvas.width()), i64::from(canvas.height()));
    let drawn: std::collections::HashSet<[u8; 3]> = (0..width)
        .flat_map(|x| (0..height).map(move |y| (x, y)))
        .filter_map(|(x, y)| canvas.get(x, y))
        .collect();
    let mut bytes = Vec::new();
    canvas.encode_png(&mut bytes).unwrap();
    let (png_width, png_height, colours) = karst_plot::testing::png_summary(&bytes);
    assert_eq!((i64::from(png_width), i64::from(png_height)), (width, height));
    assert!(colours > 20, "{colours} colours");
    let used: Vec<WaterType> = h.conduits.iter().flat_map(|c| c.segments.iter().map(|s| s.water)).collect();
    assert!(
        used.contains(&WaterType::Sump)
            && used.contains(&WaterType::Dry)
            && used.iter().any(|w| w.is_free_fall())
    );
    for w in WaterType::ALL {
        assert_eq!(drawn.contains(&colour(w)), used.contains(&w), "{w:?}: drawn iff used");
    }
}
