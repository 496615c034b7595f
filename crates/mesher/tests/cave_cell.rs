//! The automatic cave cell follows each passage's typical half-thickness (docs/mesher.md, "The
//! cave's own cell"): a segment's run of profile pieces counts once at its length-weighted
//! mean, not at its pinch; a tortuous conduit's spheres count at their axis, not at the small
//! spheres filling its sections.

use karst_artifact::read_artifact;
use karst_mesher::cave_cell;
use karst_sdf::{SdfModel, Shape};
use karst_testkit::fixture;

/// The tiny scene's model with no karst leaf: its sweeps and sphere groups serve as templates.
fn empty() -> (SdfModel, SdfModel) {
    let (_, tiny) = read_artifact::<SdfModel>(&fixture("fixtures/golden/tiny/sdf.bin")).unwrap();
    let empty = SdfModel {
        capsules: vec![],
        sweeps: vec![],
        spheres: vec![],
        chambers: vec![],
        water: vec![],
        ..tiny.clone()
    };
    (tiny, empty)
}

fn round(radius: f32) -> Shape {
    Shape { radius, ratio: 1.0, asymmetry: 0.0 }
}

#[test]
fn a_pinched_segment_counts_once_at_its_mean_half_thickness() {
    let (tiny, mut model) = empty();
    // Four 10 m pieces through half-widths 2, 2, 0.5 (a pinch), 2, 2 m: piece means 2, 1.25,
    // 1.25, 2, so the segment's mean is 1.625 m (leaf by leaf, the sections' median was 2 m).
    let radii = [2.0, 2.0, 0.5, 2.0, 2.0];
    for k in 0..4 {
        let mut s = tiny.sweeps[0];
        s.continues = k > 0;
        s.sweep.a = [10.0 * k as f32, 50.0, 50.0];
        s.sweep.b = [10.0 * (k + 1) as f32, 50.0, 50.0];
        s.sweep.start.shape = round(radii[k]);
        s.sweep.end.shape = round(radii[k + 1]);
        model.sweeps.push(s);
    }
    assert!((cave_cell(&model, 4.0, 0.0) - 1.625).abs() < 1e-6, "{}", cave_cell(&model, 4.0, 0.0));
    // Two segments: the longer one's size is the median.
    let mut other = tiny.sweeps[0];
    other.continues = false;
    other.sweep.a = [0.0, 80.0, 50.0];
    other.sweep.b = [30.0, 80.0, 50.0];
    other.sweep.start.shape = round(0.75);
    other.sweep.end.shape = round(0.75);
    model.sweeps.push(other);
    assert!((cave_cell(&model, 4.0, 0.0) - 1.625).abs() < 1e-6);
    // The pinch is still below the cell: the mesher draws it one cell thick.
    assert!(cave_cell(&model, 4.0, 0.0) > 0.5);
}

#[test]
fn a_tortuous_conduit_counts_at_its_axis_spheres_not_at_its_fillers() {
    let (tiny, mut model) = empty();
    let mut group = tiny.spheres[0].clone();
    // Two stations 3 m apart along x, each a 2 m sphere on the axis and six 0.5 m fillers
    // whose centres lie inside it. Counted leaf by leaf, each weighing its diameter, the fillers
    // (12 m) outweighed the axis (8 m) and the median was their 0.5 m.
    group.spheres.clear();
    for x in [20.0f32, 23.0] {
        group.spheres.push([x, 50.0, 50.0, 2.0]);
        for d in [[1.2, 0.0], [-1.2, 0.0], [0.0, 1.2], [0.0, -1.2], [0.8, 0.8], [-0.8, -0.8]] {
            group.spheres.push([x, 50.0 + d[0], 50.0 + d[1], 0.5]);
        }
    }
    model.spheres.push(group);
    assert!((cave_cell(&model, 4.0, 0.0) - 2.0).abs() < 1e-6, "{}", cave_cell(&model, 4.0, 0.0));
}
