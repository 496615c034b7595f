//! The surface network on hand-made scenes: flow conservation, the minimum-slope correction of
//! controller curves, the angle split at a branch, lakes and bad inputs. (The ten Table 1 types
//! on hand-built segments are a unit test of `water.rs`.)

use karst_scene::SceneView;
use karst_streams::StreamsView;
use std::path::Path;

use glam::DVec3;
use karst_geology::heightfield::{HeightGrid, write_png};
use karst_hydro::{FlowUnits, Hydro, Spring};
use karst_scene::Scene;
use karst_streams::{PoolKind, Role, Streams, StreamsError, build};
use karst_testkit::scratch;

fn hydro(springs: &[(&str, f64)]) -> Hydro {
    Hydro {
        flow_units: FlowUnits { min: 1.0, max: 1.0 },
        conduits: Vec::new(),
        nodes: Vec::new(),
        sinks: Vec::new(),
        springs: springs
            .iter()
            .map(|(name, flow)| Spring { name: name.to_string(), node: 0, flow: *flow, sinks: Vec::new() })
            .collect(),
    }
}

const HEAD: &str = "name = \"t\"\nseed = 1\n[domain]\nmin = [0, 0, 0]\nmax = [200, 120, 120]\n\
    [[geology.water_tables]]\nname = \"wt\"\nelevation = 10\n\
    [[keypoints]]\nname = \"a\"\nkind = \"sink\"\nposition = [10, 10, 20]\n";

fn scene(terrain: &str, rest: &str, folder: &Path) -> Scene {
    let text = format!("{HEAD}{terrain}\n{rest}");
    Scene::parse(&text, &folder.join("t.toml")).unwrap_or_else(|e| panic!("{e}"))
}

fn spring(name: &str, at: [f64; 3]) -> String {
    format!(
        "[[keypoints]]\nname = \"{name}\"\nkind = \"spring\"\nposition = [{}, {}, {}]\nwater_table = \"wt\"\n",
        at[0], at[1], at[2]
    )
}

/// Every node gives out what it receives; the wells give out everything that entered.
fn assert_conserved(s: &Streams) {
    let mut into = vec![0.0; s.nodes.len()];
    let mut out = vec![0.0; s.nodes.len()];
    for seg in &s.segments {
        assert!(seg.flow.is_finite() && seg.flow >= 0.0);
        out[seg.from as usize] += seg.flow;
        into[seg.to as usize] += seg.flow;
    }
    let scale = s.nodes.iter().map(|n| n.inflow).fold(1e-12, f64::max);
    for (i, n) in s.nodes.iter().enumerate() {
        assert!((n.source + n.lateral + into[i] - n.inflow).abs() <= 1e-12 * scale, "node {i}");
        if out[i] > 0.0 || !s.segments.iter().any(|g| g.from as usize == i) {
            let leaving = if s.segments.iter().any(|g| g.from as usize == i) { out[i] } else { 0.0 };
            if leaving > 0.0 {
                assert!(
                    (leaving - n.inflow).abs() <= 1e-12 * scale,
                    "node {i}: {leaving} out of {}",
                    n.inflow
                );
            }
        }
    }
    let entered: f64 = s.nodes.iter().map(|n| n.source + n.lateral).sum();
    let left: f64 = s.nodes.iter().filter(|n| n.role == Role::Well).map(|n| n.inflow).sum();
    assert!((entered - left).abs() <= 1e-9 * scale, "{entered} entered, {left} left");
}

#[test]
fn flows_are_conserved_over_noise_terrain_with_confluences() {
    let dir = scratch("conserved");
    let terrain = "[terrain]\nkind = \"noise\"\nelevation = 60\namplitude = 6\nwavelength = 60\ngradient = [-0.15, 0.0]";
    let springs: String = [[40.0, 20.0, 55.0], [40.0, 60.0, 55.0], [40.0, 100.0, 55.0], [90.0, 50.0, 40.0]]
        .iter()
        .enumerate()
        .map(|(i, p)| spring(&format!("s{i}"), *p))
        .collect();
    let s = scene(terrain, &format!("{springs}[streams]\nrunoff = 2000\n"), &dir);
    let flows = [("s0", 1.0), ("s1", 2.0), ("s2", 0.5), ("s3", 3.0)];
    let streams = build(&StreamsView::of(&s), &hydro(&flows)).unwrap();
    assert!(streams.segments.len() > 50, "{} segments", streams.segments.len());
    assert!(streams.nodes.iter().any(|n| n.lateral > 0.0), "the catchment feeds the streams");
    assert_conserved(&streams);
    // Scaled to hydro.total_discharge (1 m³/s) in proportion to the springs' flows.
    let d: Vec<f64> = streams.springs.iter().map(|m| m.discharge).collect();
    assert!((d.iter().sum::<f64>() - 1.0).abs() < 1e-12 && (d[3] / d[0] - 3.0).abs() < 1e-12, "{d:?}");
    // Same inputs, same bytes.
    assert_eq!(
        serde_json::to_string(&streams).unwrap(),
        serde_json::to_string(&build(&StreamsView::of(&s), &hydro(&flows)).unwrap()).unwrap()
    );
}

#[test]
fn climbing_curves_are_lowered_and_reported() {
    let dir = scratch("climbing");
    let terrain = "[terrain]\nkind = \"plane\"\nelevation = 80\ngradient = [-0.2, 0.0]";
    let curve = "[streams]\nmin_slope = 0.02\n[[streams.curves]]\nname = \"leat\"\nkind = \"contact\"\nflow = 0.5\n\
                 points = [[20, 60, 76], [60, 60, 70], [100, 60, 75], [140, 60, 50]]\n";
    let s = scene(terrain, &format!("{}{curve}", spring("s", [190.0, 60.0, 40.0])), &dir);
    let streams = build(&StreamsView::of(&s), &hydro(&[("s", 1.0)])).unwrap();
    let lowered: Vec<&String> = streams.reports.iter().filter(|r| r.contains("lowered")).collect();
    assert_eq!(lowered.len(), 1, "{:?}", streams.reports);
    assert!(
        lowered[0].contains("streams.curves[0] (\"leat\"): points[2] lowered from 75.00 to 69.20 m"),
        "{}",
        lowered[0]
    );
    // Along the curve every node lies at least min_slope per metre below the last.
    let curve_segments: Vec<_> =
        streams.segments.iter().filter(|g| g.curve.as_deref() == Some("leat")).collect();
    assert!(curve_segments.len() > 50, "{}", curve_segments.len());
    for g in curve_segments {
        let [a, b] = [g.from, g.to].map(|n| DVec3::from_array(streams.nodes[n as usize].position));
        let run = a.truncate().distance(b.truncate());
        assert!(a.z - b.z >= 0.02 * run - 1e-9, "{a} → {b}");
    }
    assert_conserved(&streams);
}

#[test]
fn a_branch_off_a_curve_splits_the_water_by_angle() {
    let dir = scratch("branch");
    let terrain = "[terrain]\nkind = \"plane\"\nelevation = 80\ngradient = [-0.2, 0.0]";
    let curves = "[[streams.curves]]\nname = \"main\"\nkind = \"contact\"\nflow = 1.0\ntension = 1\n\
                  points = [[20, 60, 76], [60, 60, 68], [100, 60, 60]]\n\
                  [[streams.curves]]\nname = \"side\"\nkind = \"contact\"\ntension = 1\n\
                  points = [[60, 60, 68], [90, 90, 62]]\n";
    let s = scene(terrain, &format!("{}{curves}", spring("s", [190.0, 60.0, 40.0])), &dir);
    let streams = build(&StreamsView::of(&s), &hydro(&[("s", 1.0)])).unwrap();
    let first = |name: &str| {
        streams.segments.iter().find(|g| {
            g.curve.as_deref() == Some(name) && {
                let p = streams.nodes[g.from as usize].position;
                (p[0] - 60.0).abs() < 1e-9 && (p[1] - 60.0).abs() < 1e-9
            }
        })
    };
    let (main, side) = (first("main").unwrap(), first("side").unwrap());
    // w = 1 + u·v: straight on 2, at 45° 1 + cos 45° (nearly: the segments also fall).
    let ratio = main.flow / side.flow;
    assert!(ratio > 1.1 && ratio < 1.25, "{} / {}", main.flow, side.flow);
    assert_conserved(&streams);
}

#[test]
fn a_spring_in_a_closed_hollow_fills_a_lake_and_leaves_by_its_outlet() {
    let dir = scratch("lake");
    // A bowl 60 m across walled at 57 m with a notch to the east at 52 m, in a plain falling
    // east from 50 m.
    let (nx, ny) = (101, 61);
    let heights = (0..ny)
        .flat_map(|j| {
            (0..nx).map(move |i| {
                let (x, y) = (2.0 * i as f64, 2.0 * j as f64);
                let r = ((x - 80.0).powi(2) + (y - 60.0).powi(2)).sqrt();
                let rim = if r < 30.0 {
                    45.0 + 10.0 * (r / 30.0).powi(2)
                } else if r < 36.0 {
                    57.0
                } else {
                    50.0 - 0.05 * (x - 80.0)
                };
                if (y - 60.0).abs() < 3.0 && x > 100.0 && x < 118.0 { rim.min(52.0) } else { rim }
            })
        })
        .collect();
    write_png(&dir.join("bowl.png"), &HeightGrid::new([0.0, 0.0], 2.0, nx, ny, heights), 0.0, 0.01).unwrap();
    let terrain = "[terrain]\nkind = \"heightfield\"\nfile = \"bowl.png\"\ncell_size = 2.0\norigin = [0, 0]\nvertical_scale = 0.01";
    let s = scene(
        terrain,
        &format!("{}[streams]\nlake_area = 500\ncatchment_cell = 2\n", spring("s", [80.0, 60.0, 45.0])),
        &dir,
    );
    let streams = build(&StreamsView::of(&s), &hydro(&[("s", 1.0)])).unwrap();
    let lake = streams.pools.iter().find(|p| p.kind == PoolKind::Lake).expect("a lake");
    assert!((lake.level - 52.0).abs() < 0.6, "level {}", lake.level);
    assert!(
        streams.reports.iter().any(|r| r.contains("lake") && r.contains("spring \"s\"")),
        "{:?}",
        streams.reports
    );
    assert!(
        streams.nodes.iter().any(|n| n.role == Role::Well && n.inflow > 0.99),
        "the water leaves the domain"
    );
    assert_conserved(&streams);
}

#[test]
fn a_hydro_json_of_another_scene_is_refused() {
    let dir = scratch("other");
    let s = scene("[terrain]\nkind = \"plane\"\nelevation = 80", &spring("s", [100.0, 60.0, 79.0]), &dir);
    assert_eq!(
        build(&StreamsView::of(&s), &hydro(&[("elsewhere", 1.0)])),
        Err(StreamsError::UnknownSpring("elsewhere".into()))
    );
    assert!(matches!(
        build(&StreamsView::of(&s), &hydro(&[("s", f64::NAN)])),
        Err(StreamsError::BadFlow { .. })
    ));
}
