//! The preset scenes of fixtures/scenes (Paris et al. 2021 Fig. 15, KarstNSim §2.1) are pinned
//! by a summary of their skeleton in fixtures/golden/<preset>/skeleton-summary.json: node,
//! conduit and link counts, total length, length per conduit type and the routes. Rerun with
//! `KARSTGEN_BLESS_PRESETS=1` to rewrite the summaries, and say why in the commit.
//! Every preset's routes are also checked: each sink reaches a spring it may reach (connectivity
//! matrix, last phase's springs) along the network's links, through no node twice.
//! Every network preset (these and the default scene) must stay inside the ten real-cave ranges
//! of karstnet's metrics (Collon et al. 2017), and agree with fixtures/metrics/<preset>.json,
//! the values the README's table shows (`cargo xtask metrics-table --write` rewrites both).
//! Their passages, surveyed on the carved geometry by the survey stage, must stay inside the
//! nine ranges of the surveyed caves' cross-sections (fixtures/passages/passage-ranges.json).

use std::sync::OnceLock;

use karst_artifact::{StageId, read_artifact};
use karst_metrics::ranges::{CHARACTERIZE_KEYS, real_cave_ranges};
use karst_metrics::{characterize, network_of};
use karst_pipeline::make::Selection;
use karst_scene::{KeyPointKind, Link, Scene, keypoints_of};
use karst_skeleton::{ConduitType, Skeleton};
use karst_survey::Survey;
use karstgen_tests::{root, run, scratch};

const PRESETS: [&str; 6] =
    ["branchwork", "looping", "rectilinear", "superimposed", "karstnsim", "karstnsim-2phase"];

/// The presets whose networks the README compares with real caves: the pinned ones and the
/// default scene.
const NETWORK_PRESETS: [&str; 7] =
    ["branchwork", "default", "karstnsim", "karstnsim-2phase", "looping", "rectilinear", "superimposed"];

/// The skeleton of a preset, run once (sampling, cost graph, skeleton) for all the tests here.
fn preset_skeleton(preset: &str) -> &'static Skeleton {
    static SKELETONS: OnceLock<Vec<(&str, Skeleton)>> = OnceLock::new();
    let skeletons = SKELETONS.get_or_init(|| {
        NETWORK_PRESETS
            .iter()
            .map(|&preset| {
                let out = scratch(&format!("preset-{preset}"));
                let scene = root().join(format!("fixtures/scenes/{preset}.toml"));
                for stage in [StageId::Sampling, StageId::Costgraph, StageId::Skeleton] {
                    run(&scene, &out, &Selection { only: Some(stage), ..Selection::default() }).unwrap();
                }
                let (_, skeleton) =
                    read_artifact::<Skeleton>(&out.join(StageId::Skeleton.file_name())).unwrap();
                std::fs::remove_dir_all(&out).unwrap();
                (preset, skeleton)
            })
            .collect()
    });
    &skeletons.iter().find(|(name, _)| *name == preset).expect("a network preset").1
}

fn summary(s: &Skeleton) -> serde_json::Value {
    let round = |v: f64| (v * 1000.0).round() / 1000.0;
    let mut links = s.links();
    links.sort_unstable();
    links.dedup();
    let types: serde_json::Map<String, serde_json::Value> = ConduitType::ALL
        .into_iter()
        .map(|t| (t.name().to_string(), round(s.length_of_type(t)).into()))
        .collect();
    let routes: Vec<serde_json::Value> = s
        .routes
        .iter()
        .map(|r| serde_json::json!({"sink": r.sink, "spring": r.spring, "nodes": r.nodes.len(), "cost": round(r.cost)}))
        .collect();
    serde_json::json!({
        "nodes": s.nodes.len(),
        "conduits": s.conduits.len(),
        "links": links.len(),
        "length": round(s.total_length()),
        "length_by_type": types,
        "routes": routes,
    })
}

/// Why the routes of `skeleton` break the rules of `scene`: a sink without a route, a route to a
/// spring the sink may not reach (connectivity 0, or a spring of an earlier phase), a connected
/// A sink or a spring: its row (column) of the connectivity matrix and its name.
struct End<'a> {
    row: usize,
    name: &'a str,
}

fn ends(scene: &Scene, kind: KeyPointKind) -> Vec<End<'_>> {
    keypoints_of(scene.keypoints(), kind)
        .enumerate()
        .map(|(row, (_, k))| End { row, name: &k.name })
        .collect()
}

/// (1) spring not reached, or a route that does not follow the links from its sink to its spring.
fn route_failures(scene: &Scene, skeleton: &Skeleton, preset: &str) -> Vec<String> {
    let mut failures = Vec::new();
    let springs = ends(scene, KeyPointKind::Spring);
    let active = |name: &str| scene.phases().last().is_none_or(|p| p.springs.iter().any(|s| s == name));
    let mut links = skeleton.links();
    links.sort_unstable();
    for sink in ends(scene, KeyPointKind::Sink) {
        let routes: Vec<_> = skeleton.routes.iter().filter(|r| r.sink == sink.name).collect();
        if routes.is_empty() {
            failures.push(format!("{preset}: sink {} has no route", sink.name));
        }
        for spring in &springs {
            let link = scene.connectivity().link(sink.row, spring.row);
            let reached = routes.iter().any(|r| r.spring == spring.name);
            if reached && (link == Link::None || !active(spring.name)) {
                failures.push(format!(
                    "{preset}: sink {} reaches spring {} it may not reach",
                    sink.name, spring.name
                ));
            }
            if !reached && link == Link::Connected && active(spring.name) {
                failures
                    .push(format!("{preset}: sink {} does not reach its spring {}", sink.name, spring.name));
            }
        }
    }
    for r in &skeleton.routes {
        let mut visited = r.nodes.clone();
        visited.sort_unstable();
        if let Some(w) = visited.windows(2).find(|w| w[0] == w[1]) {
            failures.push(format!("{preset}: route {} → {} visits node {} twice", r.sink, r.spring, w[0]));
        }
        let name = |i: Option<&u32>| i.and_then(|&i| skeleton.nodes[i as usize].keypoint.clone());
        let follows =
            r.nodes.windows(2).all(|w| links.binary_search(&[w[0].min(w[1]), w[0].max(w[1])]).is_ok());
        if name(r.nodes.first()).as_deref() != Some(r.sink.as_str())
            || name(r.nodes.last()).as_deref() != Some(r.spring.as_str())
            || !follows
        {
            failures.push(format!(
                "{preset}: route {} → {} does not follow the links between them",
                r.sink, r.spring
            ));
        }
    }
    failures
}

#[test]
fn preset_skeletons_match_their_golden_summaries() {
    let bless = std::env::var_os("KARSTGEN_BLESS_PRESETS").is_some();
    let mut failures = Vec::new();
    for preset in PRESETS {
        let scene = root().join(format!("fixtures/scenes/{preset}.toml"));
        let skeleton = preset_skeleton(preset);
        failures.extend(route_failures(&Scene::load(&scene).unwrap(), skeleton, preset));
        let got = summary(skeleton);
        let golden = root().join(format!("fixtures/golden/{preset}/skeleton-summary.json"));
        if bless {
            std::fs::create_dir_all(golden.parent().unwrap()).unwrap();
            std::fs::write(&golden, serde_json::to_string_pretty(&got).unwrap() + "\n").unwrap();
            continue;
        }
        let text = std::fs::read_to_string(&golden).unwrap_or_default();
        let want: serde_json::Value = serde_json::from_str(&text).unwrap_or_default();
        if want != got {
            failures.push(format!("{preset}: expected {want}\n got {got}"));
        }
    }
    assert!(failures.is_empty(), "preset skeletons changed:\n{}", failures.join("\n"));
}

/// Why a preset's karstnet metrics break the rules: a metric outside its real-cave range, or a
/// value other than the committed fixtures/metrics/<preset>.json's (the README's table).
fn range_failures(preset: &str, skeleton: &Skeleton) -> Vec<String> {
    let metrics = match characterize(&network_of(skeleton)) {
        Ok(metrics) => metrics,
        Err(e) => return vec![format!("{preset}: no karstnet metrics: {e}")],
    };
    let values: std::collections::BTreeMap<&str, f64> = metrics.to_pairs().into_iter().collect();
    let path = root().join(format!("fixtures/metrics/{preset}.json"));
    let committed: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&path).unwrap()).unwrap();
    let ranges = real_cave_ranges();
    let mut failures = Vec::new();
    for key in CHARACTERIZE_KEYS {
        let (value, range) = (values[key], &ranges[key]);
        if !range.contains(value) {
            failures.push(format!(
                "{preset}: {key} = {value} outside the real caves' [{}, {}]",
                range.min, range.max
            ));
        }
        let table = committed["payload"]["karstnet"][key]["value"].as_f64().unwrap_or(f64::NAN);
        if (table - value).abs() > 1e-9 * value.abs().max(1.0) {
            failures.push(format!(
                "{preset}: {key} = {value}, {} says {table}: run `cargo xtask metrics-table --write`",
                path.display()
            ));
        }
    }
    failures
}

#[test]
fn network_presets_stay_inside_the_real_cave_ranges() {
    let failures: Vec<String> =
        NETWORK_PRESETS.iter().flat_map(|&preset| range_failures(preset, preset_skeleton(preset))).collect();
    assert!(failures.is_empty(), "presets outside the real caves:\n{}", failures.join("\n"));
}

/// The check itself fails on a network that is no cave: a preset's first conduit alone, pulled
/// straight (one orientation, degrees 1 and 2).
#[test]
fn a_straight_conduit_is_outside_the_ranges() {
    let mut skeleton = preset_skeleton("branchwork").clone();
    let mut conduit = skeleton.conduits[0].clone();
    let n = conduit.nodes.len();
    skeleton.nodes.truncate(n);
    for (i, node) in skeleton.nodes.iter_mut().enumerate() {
        node.position = [10.0 * i as f64, 0.0, 0.0];
    }
    conduit.nodes = (0..n as u32).collect();
    skeleton.conduits = vec![conduit];
    let failures = range_failures("branchwork", &skeleton);
    assert!(failures.iter().any(|f| f.contains("outside the real caves")), "{failures:?}");
}

/// The nine statistics of the passages of `preset`'s default run (sampling to sdf, then the
/// survey) that fall outside the surveyed caves' ranges.
fn passage_failures(preset: &str) -> Vec<String> {
    let out = scratch(&format!("passages-{preset}"));
    let scene = root().join(format!("fixtures/scenes/{preset}.toml"));
    run(&scene, &out, &Selection { to: Some(StageId::Sdf), ..Selection::default() }).unwrap();
    run(&scene, &out, &Selection { only: Some(StageId::Survey), ..Selection::default() }).unwrap();
    let (_, survey) = read_artifact::<Survey>(&out.join(StageId::Survey.file_name())).unwrap();
    std::fs::remove_dir_all(&out).unwrap();
    assert_eq!(survey.statistics.len(), 9, "{preset}: the survey's statistics");
    survey
        .statistics
        .iter()
        .filter(|(_, s)| !s.inside)
        .map(|(name, s)| {
            format!("{preset}: {name} = {:?} outside the surveyed caves' [{}, {}]", s.value, s.min, s.max)
        })
        .collect()
}

#[test]
fn network_presets_passages_stay_inside_the_surveyed_caves_ranges() {
    let failures: Vec<String> = NETWORK_PRESETS.iter().flat_map(|&preset| passage_failures(preset)).collect();
    assert!(failures.is_empty(), "passages unlike the surveyed caves':\n{}", failures.join("\n"));
}
