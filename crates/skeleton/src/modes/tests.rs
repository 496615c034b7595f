//! Both synthesis modes on a small two-spring scene: reachability under the connectivity
//! matrix, order independence without cohesion, the effect of cohesion, forced links, and the
//! mechanisms that make networks pass for real caves (tributaries, gamma-mode cohesion,
//! meanders).

use std::collections::{BTreeMap, BTreeSet};
use std::path::Path;

use crate::error::SkeletonError;
use crate::modes::karstnsim;
use crate::payload::Skeleton;
use crate::route::ends::End;
use crate::route::search::EdgeCosts;
use crate::view::SkeletonView;
use karst_costgraph::CostgraphView;
use karst_costgraph::{CostGraph, Costing};
use karst_sampling::Samples;
use karst_sampling::SamplingView;
use karst_scene::{Scene, SceneView};

const SCENE: &str = r#"
name = "two-springs"
seed = 11
[domain]
min = [0, 0, 0]
max = [300, 200, 80]
[terrain]
kind = "plane"
elevation = 78
[[geology.water_tables]]
name = "east"
elevation = 30
origin = [295, 100]
dip = 1.0
dip_direction = 90
[[geology.water_tables]]
name = "west"
elevation = 20
[[keypoints]]
name = "s1"
kind = "sink"
position = [60, 40, 75]
[[keypoints]]
name = "s2"
kind = "sink"
position = [150, 160, 75]
[[keypoints]]
name = "s3"
kind = "sink"
position = [200, 60, 75]
[[keypoints]]
name = "s4"
kind = "sink"
position = [120, 100, 75]
[[keypoints]]
name = "east"
kind = "spring"
position = [295, 100, 30]
water_table = "east"
[[keypoints]]
name = "west"
kind = "spring"
position = [5, 100, 20]
water_table = "west"
[connectivity]
matrix = [[0, 1], [2, 2], [1, 1], [1, 0]]
[sampling]
radius = 9.0
[costgraph]
k = 16
"#;

/// The mechanisms the defaults turn on (issue 38), off unless a test sets them: these tests
/// check one mechanism at a time.
const PLAIN: [(&str, &str); 4] = [
    ("cohesion_vadose", "1.0"),
    ("cohesion_phreatic", "1.0"),
    ("amplification_steps", "0"),
    ("sinuosity", "1.0"),
];

/// The scene with `extra` and, in `[skeleton]`, the [`PLAIN`] values `extra` does not set.
fn scene(extra: &str) -> Scene {
    let plain: String = PLAIN
        .iter()
        .filter(|(key, _)| !extra.contains(&format!("{key} =")))
        .map(|(key, value)| format!("{key} = {value}\n"))
        .collect();
    let extra = match extra.find("[skeleton]\n") {
        Some(at) => format!("{}[skeleton]\n{plain}{}", &extra[..at], &extra[at + "[skeleton]\n".len()..]),
        None => format!("{extra}\n[skeleton]\n{plain}"),
    };
    with_defaults(&extra)
}

/// The scene with `extra` and the defaults for everything else.
fn with_defaults(extra: &str) -> Scene {
    Scene::parse(&format!("{SCENE}\n{extra}"), Path::new("two-springs.toml")).unwrap()
}

/// The samples and the cost graph of `scene`, costed on demand (as the skeleton stage does).
fn inputs(scene: &Scene) -> (Samples, CostGraph) {
    let samples = karst_sampling::build(&SamplingView::of(scene)).unwrap();
    let graph = karst_costgraph::build(&CostgraphView::of(scene), &samples).unwrap();
    graph.cost_from(&CostgraphView::of(scene), &samples.positions, Costing::OnDemand).unwrap();
    (samples, graph)
}

/// The skeleton of `scene` (the stage's build on its view).
fn build(scene: &Scene, samples: &Samples, graph: &CostGraph) -> Result<Skeleton, SkeletonError> {
    crate::build::build(&SkeletonView::of(scene), samples, graph)
}

fn sinks_in_order(scene: &Scene) -> Vec<End<'_>> {
    crate::route::ends::sinks_in_order(&SkeletonView::of(scene))
}

fn route(
    scene: &Scene,
    samples: &Samples,
    graph: &CostGraph,
    sinks: &[End],
) -> BTreeMap<(String, String), Vec<usize>> {
    let cost_set = |_: &str| -> &dyn EdgeCosts { graph };
    let view = SkeletonView::of(scene);
    let phase = karstnsim::PhaseSetup::single(&view, graph);
    karstnsim::route(&view, samples, graph, &cost_set, sinks, &phase)
        .unwrap()
        .routes
        .into_iter()
        .map(|(r, path)| ((r.sink, r.spring), path))
        .collect()
}

#[test]
fn every_sink_reaches_the_springs_it_may_reach() {
    let scene = scene("");
    let (samples, graph) = inputs(&scene);
    let skeleton = build(&scene, &samples, &graph).unwrap();
    let pairs: BTreeSet<(&str, &str)> =
        skeleton.routes.iter().map(|r| (r.sink.as_str(), r.spring.as_str())).collect();
    let expected_fixed = [("s1", "west"), ("s3", "east"), ("s3", "west"), ("s4", "east")];
    for p in expected_fixed {
        assert!(pairs.contains(&p), "{p:?} missing from {pairs:?}");
    }
    assert!(!pairs.contains(&("s1", "east")) && !pairs.contains(&("s4", "west")));
    assert_eq!(skeleton.routes.iter().filter(|r| r.sink == "s2").count(), 1, "uncertain: one spring");
    for r in &skeleton.routes {
        let name = |i: &u32| skeleton.nodes[*i as usize].keypoint.clone();
        assert_eq!(name(r.nodes.first().unwrap()).as_deref(), Some(r.sink.as_str()));
        assert_eq!(name(r.nodes.last().unwrap()).as_deref(), Some(r.spring.as_str()));
        assert!(r.nodes.windows(2).all(|w| linked(&skeleton, w[0], w[1])), "route follows the links");
    }
}

fn linked(s: &Skeleton, a: u32, b: u32) -> bool {
    s.links().contains(&[a.min(b), a.max(b)])
}

#[test]
fn without_cohesion_routes_do_not_depend_on_sink_order() {
    let scene = scene("[skeleton]\ncohesion_vadose = 1.0\ncohesion_phreatic = 1.0\n");
    let (samples, graph) = inputs(&scene);
    let order = sinks_in_order(&scene);
    let reversed: Vec<End> = order.iter().rev().copied().collect();
    assert_eq!(route(&scene, &samples, &graph, &order), route(&scene, &samples, &graph, &reversed));
}

#[test]
fn the_least_costs_to_the_springs_change_no_route() {
    for extra in ["", "[skeleton]\ncohesion_vadose = 0.2\ncohesion_phreatic = 0.2\n"] {
        let scene = scene(extra);
        let (samples, graph) = inputs(&scene);
        let order = sinks_in_order(&scene);
        let cost_set = |_: &str| -> &dyn EdgeCosts { &graph };
        let view = SkeletonView::of(&scene);
        let phase = karstnsim::PhaseSetup::single(&view, &graph);
        let routes = |legs_worth: usize| {
            let run =
                || karstnsim::route_mapping(&view, &samples, (&graph, &cost_set), &order, &phase, legs_worth);
            let paths = |r: karstnsim::PhaseRoutes| -> Vec<(String, String, Vec<usize>)> {
                r.routes.into_iter().map(|(r, path)| (r.sink, r.spring, path)).collect()
            };
            let one_thread = rayon::ThreadPoolBuilder::new().num_threads(1).build().expect("a pool");
            (paths(run().unwrap()), paths(one_thread.install(run).unwrap()))
        };
        let (plain, plain_alone) = routes(usize::MAX);
        let (mapped, mapped_alone) = routes(1);
        assert!(!plain.is_empty());
        assert_eq!(mapped, plain, "{extra:?}");
        assert_eq!(mapped_alone, plain_alone, "{extra:?}");
        assert_eq!(mapped_alone, plain, "{extra:?}");
    }
}

fn distinct_links(routes: &BTreeMap<(String, String), Vec<usize>>) -> usize {
    let links: BTreeSet<(usize, usize)> =
        routes.values().flat_map(|p| p.windows(2).map(|w| (w[0].min(w[1]), w[0].max(w[1])))).collect();
    links.len()
}

#[test]
fn cohesion_gathers_conduits_and_depends_on_order() {
    let loose = scene("");
    let tight = scene("[skeleton]\ncohesion_vadose = 0.2\ncohesion_phreatic = 0.2\n");
    let (samples, graph) = inputs(&loose);
    let order = sinks_in_order(&tight);
    let a = route(&tight, &samples, &graph, &order);
    let free = route(&loose, &samples, &graph, &order);
    assert!(
        distinct_links(&a) < distinct_links(&free),
        "{} vs {}",
        distinct_links(&a),
        distinct_links(&free)
    );
}

#[test]
fn gamma_mode_joins_every_key_point_and_honours_forced_links() {
    let scene_rng = scene("[skeleton]\nmode = \"gamma\"\ngamma = 60.0\n");
    let (samples, graph) = inputs(&scene_rng);
    let rng = build(&scene_rng, &samples, &graph).unwrap();
    let on_network: BTreeSet<&str> = rng.nodes.iter().filter_map(|n| n.keypoint.as_deref()).collect();
    assert_eq!(on_network.len(), scene_rng.keypoints().len());
    let dense = build(&scene("[skeleton]\nmode = \"gamma\"\ngamma = 0.5\n"), &samples, &graph).unwrap();
    assert!(dense.total_length() > rng.total_length());
    let forced = scene("[skeleton]\nmode = \"gamma\"\ngamma = 60.0\nforced_links = [[\"s1\", \"east\"]]\n");
    // Forced links are part of the cost graph's scene sections: the graph is made again.
    let (samples, graph) = inputs(&forced);
    let with_link = build(&forced, &samples, &graph).unwrap();
    assert!(with_link.total_length() > rng.total_length());
    assert!(!with_link.routes.is_empty());
}

/// The links of a skeleton as pairs of samples, which do not depend on node numbering.
fn sample_links(s: &Skeleton) -> BTreeSet<(u32, u32)> {
    s.links()
        .iter()
        .map(|[a, b]| {
            let (a, b) = (s.nodes[*a as usize].sample, s.nodes[*b as usize].sample);
            (a.min(b), a.max(b))
        })
        .collect()
}

#[test]
fn a_smaller_gamma_never_removes_a_conduit_a_larger_gamma_keeps() {
    // Six waypoints inside the rock give the γ-skeleton pairs to prune. Without tortuosity,
    // amplification or dead ends, the network is the union of the kept pairs' paths, so the
    // pair monotonicity of the rule must hold for the conduits themselves.
    let waypoints: String =
        [[80, 150, 40], [150, 60, 35], [230, 140, 45], [120, 100, 25], [260, 70, 30], [40, 90, 50]]
            .iter()
            .enumerate()
            .map(|(i, p)| format!("[[keypoints]]\nname = \"w{i}\"\nkind = \"waypoint\"\nposition = {p:?}\n"))
            .collect();
    let build = |gamma: f64| {
        let scene = scene(&format!("{waypoints}[skeleton]\nmode = \"gamma\"\ngamma = {gamma}\n"));
        let (samples, graph) = inputs(&scene);
        sample_links(&build(&scene, &samples, &graph).unwrap())
    };
    let gammas = [0.8, 1.2, 1.7, 2.0, 3.0, 60.0];
    let networks: Vec<_> = gammas.iter().map(|&g| build(g)).collect();
    for (i, w) in networks.windows(2).enumerate() {
        let lost: Vec<_> = w[1].difference(&w[0]).collect();
        assert!(lost.is_empty(), "γ {} removes {} links γ {} keeps", gammas[i], lost.len(), gammas[i + 1]);
    }
    assert!(networks[0].len() > networks[gammas.len() - 1].len(), "γ must matter on this scene");
}

#[test]
fn bad_skeleton_parameters_are_refused() {
    let bad = |extra: &str| {
        Scene::parse(&format!("{SCENE}\n{extra}"), Path::new("x.toml")).unwrap_err().to_string()
    };
    assert!(bad("[skeleton]\ngamma = 0.0\n").contains("skeleton.gamma"));
    assert!(bad("[skeleton]\ncohesion_vadose = 1.5\n").contains("skeleton.cohesion_vadose"));
    assert!(bad("[skeleton]\ntortuosity = 1.2\n").contains("skeleton.tortuosity"));
    assert!(bad("[skeleton]\ndead_end_fraction = -0.1\n").contains("skeleton.dead_end_fraction"));
    let e = bad("[skeleton]\nforced_links = [[\"s1\", \"nowhere\"]]\n");
    assert!(e.contains("skeleton.forced_links[0]") && e.contains("nowhere"), "{e}");
}

fn cycles(s: &Skeleton) -> i64 {
    let mut links = s.links();
    links.sort_unstable();
    links.dedup();
    links.len() as i64 - s.nodes.len() as i64 + 1
}

fn route_positions(s: &Skeleton) -> Vec<Vec<[f64; 3]>> {
    s.routes.iter().map(|r| r.nodes.iter().map(|&i| s.nodes[i as usize].position).collect()).collect()
}

#[test]
fn amplification_adds_dry_branches_dead_ends_and_loops() {
    let base = scene("");
    let (samples, graph) = inputs(&base);
    let plain = build(&base, &samples, &graph).unwrap();
    let amplify = |fraction: f64| {
        let extra = format!(
            "[skeleton]\namplification_steps = 2\namplification_points = 4\ndead_end_fraction = {fraction}\n"
        );
        build(&scene(&extra), &samples, &graph).unwrap()
    };
    let dead = amplify(1.0);
    let looped = amplify(0.0);
    for s in [&dead, &looped] {
        assert!(s.total_length() > plain.total_length());
        assert_eq!(route_positions(s), route_positions(&plain), "amplification leaves the routes alone");
    }
    let degree_one = |s: &Skeleton| {
        let mut degree = vec![0; s.nodes.len()];
        for [a, b] in s.links() {
            degree[a as usize] += 1;
            degree[b as usize] += 1;
        }
        degree.iter().filter(|d| **d == 1).count()
    };
    assert!(degree_one(&dead) > degree_one(&plain));
    assert_eq!(cycles(&dead), cycles(&plain), "dead ends close no loop");
    assert!(cycles(&looped) > cycles(&plain), "interior points close loops");
}

#[test]
fn tortuosity_grows_with_theta_and_stays_in_the_bedrock() {
    let base = scene("");
    let (samples, graph) = inputs(&base);
    let straight = build(&base, &samples, &graph).unwrap();
    let wiggle =
        |theta: f64| build(&scene(&format!("[skeleton]\ntortuosity = {theta}\n")), &samples, &graph).unwrap();
    let (calm, wild) = (wiggle(0.0), wiggle(1.0));
    for s in [&calm, &wild] {
        assert_eq!(s.links().len(), 4 * straight.links().len(), "two levels: four segments per link");
        for n in &s.nodes {
            let p = glam::DVec3::from_array(n.position);
            assert!(base.terrain().in_bedrock(base.domain(), p), "{p}");
        }
        for r in &s.routes {
            assert!(r.nodes.windows(2).all(|w| linked(s, w[0], w[1])), "routes follow the refined links");
        }
    }
    let excess = |s: &Skeleton| s.total_length() / straight.total_length() - 1.0;
    assert!(excess(&calm) < 1e-3, "{}", excess(&calm));
    assert!(excess(&wild) > 10.0 * excess(&calm).max(1e-4), "{} vs {}", excess(&wild), excess(&calm));
}

const TWO_PHASES: &str = r#"
[[phases]]
name = "high"
springs = ["east"]
[[phases]]
name = "low"
springs = ["west"]
inherited_cost = 0.2
weights = { s2 = 5.0 }
"#;

#[test]
fn a_later_phase_keeps_the_relict_conduits_and_reuses_them() {
    let scene = scene(TWO_PHASES);
    let (samples, graph) = inputs(&scene);
    let s = build(&scene, &samples, &graph).unwrap();
    let phases: BTreeSet<u32> = s.conduits.iter().map(|c| c.phase).collect();
    assert_eq!(phases, BTreeSet::from([0, 1]));
    assert!(s.routes.iter().all(|r| r.spring == "west"), "routes are the last phase's drainage");
    assert_eq!(s.routes.iter().find(|r| r.sink == "s2").unwrap().weight, 5.0);
    assert!(s.routes.iter().all(|r| r.sink != "s4"), "s4 may only drain east: it sits the low phase out");
    // The east spring, active only in the first phase, is still on the (relict) network.
    assert!(s.nodes.iter().any(|n| n.keypoint.as_deref() == Some("east")));
    let relict: BTreeSet<[u32; 2]> = s
        .conduits
        .iter()
        .filter(|c| c.phase == 0)
        .flat_map(|c| c.nodes.windows(2).map(|w| [w[0].min(w[1]), w[0].max(w[1])]))
        .collect();
    let reused = s
        .routes
        .iter()
        .flat_map(|r| r.nodes.windows(2))
        .filter(|w| relict.contains(&[w[0].min(w[1]), w[0].max(w[1])]))
        .count();
    assert!(reused > 0, "the low phase reuses conduits of the high phase");
}

#[test]
fn bad_phases_are_refused() {
    let bad = |extra: &str| {
        Scene::parse(&format!("{SCENE}\n{extra}"), Path::new("x.toml")).unwrap_err().to_string()
    };
    let e = bad("[[phases]]\nname = \"p\"\nsprings = [\"nowhere\"]\n");
    assert!(e.contains("phases[0].springs") && e.contains("nowhere"), "{e}");
    let e = bad("[[phases]]\nname = \"p\"\nsprings = [\"east\"]\ninherited_cost = 0\n");
    assert!(e.contains("phases[0].inherited_cost"), "{e}");
    let e = bad("[skeleton]\nmode = \"gamma\"\n[[phases]]\nname = \"p\"\nsprings = [\"east\"]\n");
    assert!(e.contains("phases") && e.contains("karstnsim"), "{e}");
}

/// The cost graph without the edges that cross the plane x = 150: two halves.
fn cut_in_two(samples: &Samples, graph: &CostGraph) -> CostGraph {
    let side = |v: usize| samples.positions[v][0] < 150.0;
    let lists = (0..graph.node_count())
        .map(|u| {
            graph.out_edges(u).filter(|(v, _)| side(*v) == side(u)).map(|(v, c)| (v as u32, c)).collect()
        })
        .collect();
    CostGraph::from_lists(lists)
}

#[test]
fn unreachable_key_points_are_named() {
    let gamma = scene("[skeleton]\nmode = \"gamma\"\n");
    let (samples, graph) = inputs(&gamma);
    let cut = cut_in_two(&samples, &graph);
    let e = build(&gamma, &samples, &cut).unwrap_err();
    assert_eq!(e, SkeletonError::KeyPointsApart { a: "s1".into(), b: "s2".into() });
    let e = build(&scene(""), &samples, &cut).unwrap_err();
    let named = [("s3", "west"), ("s4", "east")].map(|(sink, spring)| SkeletonError::SinkCannotReachSpring {
        sink: sink.into(),
        spring: spring.into(),
    });
    assert!(named.contains(&e), "{e}");
}

const WAYPOINT_AND_DEAD_END: &str = r#"
[[keypoints]]
name = "passage"
kind = "waypoint"
position = [100, 170, 50]
[[keypoints]]
name = "chamber"
kind = "dead_end"
position = [250, 180, 45]
"#;

#[test]
fn waypoints_and_dead_ends_join_the_network() {
    for mode in ["karstnsim", "gamma"] {
        let scene = scene(&format!("{WAYPOINT_AND_DEAD_END}\n[skeleton]\nmode = \"{mode}\"\n"));
        let (samples, graph) = inputs(&scene);
        let s = build(&scene, &samples, &graph).unwrap();
        let node_of = |name: &str| s.nodes.iter().position(|n| n.keypoint.as_deref() == Some(name));
        let degree = |i: usize| s.links().iter().filter(|l| l.contains(&(i as u32))).count();
        let chamber = node_of("chamber").unwrap_or_else(|| panic!("{mode}: dead end missing"));
        assert_eq!(degree(chamber), 1, "{mode}: a dead end is joined once");
        let passage = node_of("passage").unwrap_or_else(|| panic!("{mode}: waypoint missing"));
        assert!(degree(passage) >= 2, "{mode}: a waypoint is passed through");
    }
}

fn degrees(s: &Skeleton) -> Vec<usize> {
    let mut degree = vec![0; s.nodes.len()];
    for [a, b] in s.links() {
        degree[a as usize] += 1;
        degree[b as usize] += 1;
    }
    degree
}

#[test]
fn hierarchical_tributaries_meet_passages_at_t_junctions() {
    let base = scene("");
    let (samples, graph) = inputs(&base);
    let plain = build(&base, &samples, &graph).unwrap();
    let tributaries = |ratio: f64| {
        let extra = format!(
            "[skeleton]\namplification_steps = 3\namplification_points = 2\ndead_end_fraction = 1.0\n\
             amplification_length = [18.0, 120.0]\namplification_exponent = 1.2\namplification_ratio = {ratio}\n"
        );
        build(&scene(&extra), &samples, &graph).unwrap()
    };
    let (flat, horton) = (tributaries(1.0), tributaries(2.0));
    let count = |s: &Skeleton, f: &dyn Fn(usize) -> bool| degrees(s).into_iter().filter(|d| f(*d)).count();
    for s in [&flat, &horton] {
        assert_eq!(route_positions(s), route_positions(&plain), "tributaries are dry");
        assert_eq!(cycles(s), cycles(&plain), "dead ends close no loop");
        // Joins land on a passage (degree 2 → 3), never on a junction: no new node of degree 4+.
        assert_eq!(count(s, &|d| d >= 4), count(&plain, &|d| d >= 4));
    }
    let ends = |s: &Skeleton| count(s, &|d| d == 1) - count(&plain, &|d| d == 1);
    assert!(ends(&flat) >= 4 && ends(&horton) > ends(&flat), "{} vs {}", ends(&horton), ends(&flat));
}

#[test]
fn cohesion_in_gamma_mode_merges_paths_into_trunks() {
    let free = scene("[skeleton]\nmode = \"gamma\"\ngamma = 1.5\n");
    let (samples, graph) = inputs(&free);
    let tight =
        scene("[skeleton]\nmode = \"gamma\"\ngamma = 1.5\ncohesion_vadose = 0.3\ncohesion_phreatic = 0.3\n");
    let (a, b) = (build(&free, &samples, &graph).unwrap(), build(&tight, &samples, &graph).unwrap());
    let joined = |s: &Skeleton| s.nodes.iter().filter(|n| n.keypoint.is_some()).count();
    assert_eq!(joined(&b), joined(&a), "every key point stays on the network");
    assert!(b.total_length() < 0.9 * a.total_length(), "{} vs {}", b.total_length(), a.total_length());
}

#[test]
fn meanders_lengthen_conduits_within_the_bedding_plane() {
    // No joint either (the assumed ones are planes to bend in too).
    let base = scene("assumed_joints = false\n");
    let (samples, graph) = inputs(&base);
    let straight = build(&base, &samples, &graph).unwrap();
    let bent =
        build(&scene("assumed_joints = false\n[skeleton]\nsinuosity = 1.2\n"), &samples, &graph).unwrap();
    let ratio = bent.total_length() / straight.total_length();
    assert!(ratio > 1.05 && ratio < 1.25, "{ratio}");
    // No horizon: the bedding is horizontal, so every original node keeps its elevation.
    let mut moved = 0;
    for (a, b) in straight.nodes.iter().zip(&bent.nodes) {
        assert!((a.position[2] - b.position[2]).abs() < 1e-9, "{:?} → {:?}", a.position, b.position);
        moved += usize::from(a.position != b.position);
    }
    assert!(moved > 0);
    for r in &bent.routes {
        assert!(r.nodes.windows(2).all(|w| linked(&bent, w[0], w[1])), "routes follow the bent links");
    }
    assert!(
        bent.nodes
            .iter()
            .all(|n| base.terrain().in_bedrock(base.domain(), glam::DVec3::from_array(n.position)))
    );
}

#[test]
fn realism_parameters_out_of_range_are_refused() {
    let bad = |extra: &str| {
        Scene::parse(&format!("{SCENE}\n{extra}"), Path::new("x.toml")).unwrap_err().to_string()
    };
    let e = bad("[skeleton]\namplification_length = [5.0, 100.0]\n");
    assert!(e.contains("skeleton.amplification_length") && e.contains("sampling.radius"), "{e}");
    assert!(bad("[skeleton]\namplification_length = [50.0, 20.0]\n").contains("not a range"));
    assert!(bad("[skeleton]\namplification_ratio = 0.5\n").contains("skeleton.amplification_ratio"));
    assert!(bad("[skeleton]\nconfluence_attraction = 2.0\n").contains("skeleton.confluence_attraction"));
    assert!(bad("[skeleton]\nsinuosity = 0.9\n").contains("skeleton.sinuosity"));
    assert!(bad("[skeleton]\nmeander_wavelength = [0.0, 10.0]\n").contains("skeleton.meander_wavelength"));
}

#[test]
fn defaults_derived_from_the_scene_are_recorded_and_shape_the_network() {
    let scene = with_defaults("");
    let (samples, graph) = inputs(&scene);
    let skeleton = build(&scene, &samples, &graph).unwrap();
    let derived = &skeleton.derived;
    // [sampling] gives the radius (9 m): the shortest tributary is twice it; the sinks' median
    // nearest-neighbour distance (about 78 m) halved is below 10 radii, so the longest is 90 m.
    assert_eq!(derived.get("sampling.radius"), None);
    assert_eq!(derived["skeleton.amplification_length"], serde_json::json!([18.0, 90.0]));
    // Ten passage widths of the default radii [0.5, 4] m.
    assert_eq!(derived["skeleton.meander_wavelength"], serde_json::json!([10.0, 80.0]));
    let points = derived["skeleton.amplification_points"].as_u64().unwrap();
    assert!(points >= 2, "{points}");
    // Dead-end tributaries: many nodes of degree 1 beyond the five key points.
    let ends = degrees(&skeleton).iter().filter(|d| **d == 1).count();
    assert!(ends > 5 + points as usize / 2, "{ends} dead ends for {points} first-step tributaries");
    let text = crate::resolved_toml(&skeleton).unwrap();
    assert!(text.contains("[skeleton]\namplification_length = [18.0,90.0]\n"), "{text}");
    // The flat ground has no lineament: the assumed joint sets run north–south and east–west.
    let joints = &text[text.find("[[geology.fractures]]").expect("the assumed joints are recorded")..];
    let joints = &joints[..joints.find("\n[skeleton]").unwrap_or(joints.len())];
    assert!(joints.contains("azimuth = 0.0") && joints.contains("azimuth = 90.0"), "{joints}");
    // Copied into the scene, they pin the same network.
    let pinned = with_defaults(joints);
    let (_, pinned_graph) = inputs(&pinned);
    let again = build(&pinned, &samples, &pinned_graph).unwrap();
    assert_eq!(again.derived.get("geology.fractures"), None);
    assert_eq!(sample_links(&again), sample_links(&skeleton));
    assert_eq!(
        route_positions(&again),
        route_positions(&skeleton),
        "the meanders bend within the same joints"
    );
}

#[test]
fn without_fracture_families_the_routes_follow_the_assumed_joints() {
    let share_along = |extra: &str| {
        let scene = with_defaults(extra);
        let (samples, graph) = inputs(&scene);
        let skeleton = build(&scene, &samples, &graph).unwrap();
        let (mut along, mut total) = (0.0, 0.0);
        for (a, b) in sample_links(&skeleton) {
            let (p, q) = (samples.positions[a as usize], samples.positions[b as usize]);
            let (dx, dy) = (q[0] - p[0], q[1] - p[1]);
            let length = dx.hypot(dy);
            // Within 10° of north–south or east–west.
            let off_axis = dx.abs().min(dy.abs()) / length.max(1e-9);
            total += length;
            along += if off_axis < 10f64.to_radians().sin() { length } else { 0.0 };
        }
        along / total
    };
    let assumed = share_along("");
    let isotropic = share_along("assumed_joints = false\n");
    // Two sets of ±10° hold 2/9 of the azimuths of an isotropic network.
    assert!(assumed > isotropic + 0.15, "{assumed} along the joints, {isotropic} without them");
}

#[test]
fn values_the_scene_gives_are_not_derived() {
    let scene = with_defaults(
        "assumed_joints = false\n[skeleton]\namplification_points = 3\namplification_length = [20.0, 60.0]\nmeander_wavelength = [30.0, 50.0]\n",
    );
    let (samples, graph) = inputs(&scene);
    let skeleton = build(&scene, &samples, &graph).unwrap();
    assert!(skeleton.derived.is_empty(), "{:?}", skeleton.derived);
    assert_eq!(crate::resolved_toml(&skeleton), None);
}

#[test]
fn the_sampling_radius_left_out_is_derived_from_the_bedrock() {
    let text = SCENE.replace("[sampling]\nradius = 9.0\n", "");
    let scene = Scene::parse(&text, Path::new("two-springs.toml")).unwrap();
    let view = SkeletonView::of(&scene);
    // 300 × 200 m under a flat ground at 78 m: 4.68e6 m³, (0.725 × 4.68e6 / 30000)^⅓ ≈ 4.84 m.
    let r = crate::defaults::sampling_radius(&view);
    assert!((r - 4.84).abs() < 0.01, "{r}");
    let (samples, _) = inputs(&scene);
    assert!((25_000..=40_000).contains(&samples.len()), "{} samples", samples.len());
}
