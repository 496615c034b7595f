//! Bad input of the cost graph: every case is refused with a message naming what is wrong.

use karst_costgraph::CostgraphView;
use karst_scene::SceneView;
use std::path::Path;

use karst_costgraph::{CostGraphError, build};
use karst_sampling::SpacingField;
use karst_sampling::{Samples, Tag};
use karst_scene::{Scene, SceneError};

const SCENE: &str = r#"
name = "t"
[domain]
min = [0, 0, 0]
max = [100, 100, 50]
[terrain]
kind = "plane"
elevation = 50
[[geology.water_tables]]
name = "wt"
elevation = 10
[[keypoints]]
name = "doline"
kind = "sink"
position = [5, 5, 45]
[[keypoints]]
name = "resurgence"
kind = "spring"
position = [95, 95, 10]
water_table = "wt"
"#;

fn scene(extra: &str) -> Result<Scene, SceneError> {
    Scene::parse(&format!("{SCENE}{extra}"), Path::new("scene.toml"))
}

/// The two key points, then a grid of samples every `step` metres in x and y at z = 25 inside
/// `[x0, x1]`.
fn samples(step: f64, x0: f64, x1: f64) -> Samples {
    let mut positions = vec![[5.0, 5.0, 45.0], [95.0, 95.0, 10.0]];
    let mut x = x0;
    while x <= x1 {
        let mut y = 0.0;
        while y <= 100.0 {
            positions.push([x, y, 25.0]);
            y += step;
        }
        x += step;
    }
    let tags =
        (0..positions.len()).map(|i| if i < 2 { Tag::KeyPoint(i as u32) } else { Tag::Volume }).collect();
    let radius_field =
        SpacingField { origin: [0.0; 3], cell: 1.0, size: [1, 1, 1], values: vec![step as f32] };
    Samples { positions, tags, radius: step, radius_field }
}

#[test]
fn k_must_be_below_the_sample_count() {
    let scene = scene("[costgraph]\nk = 16").unwrap();
    let err = build(&CostgraphView::of(&scene), &samples(50.0, 0.0, 50.0)).unwrap_err();
    assert!(matches!(err, CostGraphError::TooFewSamples { k: 16, samples: 8 }), "{err}");
}

#[test]
fn isolated_key_point_is_named() {
    let scene = scene("[costgraph]\nk = 4\nmax_edge_length = 15.0").unwrap();
    let err = build(&CostgraphView::of(&scene), &samples(10.0, 0.0, 100.0)).unwrap_err().to_string();
    assert!(err.contains("\"doline\"") && err.contains("max_edge_length = 15"), "{err}");
}

#[test]
fn unreachable_spring_names_the_sink_and_the_spring() {
    // Two clusters 40 m apart: the sink's and the spring's.
    let scene = scene("[costgraph]\nk = 4\nmax_edge_length = 30.0").unwrap();
    let mut s = samples(10.0, 0.0, 30.0);
    let far = samples(10.0, 70.0, 100.0);
    s.positions.extend(&far.positions[2..]);
    s.tags.extend(&far.tags[2..]);
    let err = build(&CostgraphView::of(&scene), &s).unwrap_err().to_string();
    assert!(err.contains("sink \"doline\" cannot reach spring \"resurgence\""), "{err}");
}

#[test]
fn negative_and_nan_weights_and_k_zero_are_refused() {
    let problems = match scene("[costgraph]\nk = 0\nalpha_fracture = -1.0\nw_horizon = nan\ncost_floor = 0.0")
    {
        Err(SceneError::Invalid { problems, .. }) => {
            problems.iter().map(|p| p.to_string()).collect::<Vec<_>>()
        }
        other => panic!("accepted: {other:?}"),
    };
    for field in ["costgraph.k", "costgraph.alpha_fracture", "costgraph.w_horizon", "costgraph.cost_floor"] {
        assert!(problems.iter().any(|p| p.contains(field)), "{field} not reported: {problems:?}");
    }
    assert!(problems.iter().all(|p| p.starts_with(':')), "{problems:?}");
}

#[test]
fn the_graph_of_good_input_has_positive_costs() {
    let scene = scene("[costgraph]\nk = 8").unwrap();
    let samples = samples(10.0, 0.0, 100.0);
    let graph = build(&CostgraphView::of(&scene), &samples).unwrap();
    assert_eq!(graph.edge_count(), 8 * graph.node_count());
    graph.cost_from(&CostgraphView::of(&scene), &samples.positions, karst_costgraph::Costing::Every).unwrap();
    assert!((0..graph.node_count()).all(|u| graph.row_costs(0, u).iter().all(|&c| c > 0.0)));
    assert_eq!(graph.cost_set_of_water_table("wt"), Some(0));
}
