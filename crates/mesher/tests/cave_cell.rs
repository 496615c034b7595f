//! The automatic cave cell follows the passages' half-thickness (docs/mesher.md, "The cave's
//! own cell"): each piece of a segment's profile counts at its depth, weighted by its length, so
//! a short pinch does not set the cell; a tortuous conduit's spheres (`passage_detail = "off"`)
//! count at their axis, not at the small spheres filling its sections.

use karst_artifact::read_artifact;
use karst_mesher::cave_cell;
use karst_sdf::{SdfModel, SectionSpec, Shape};
use karst_skeleton::ConduitType;
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

fn round(radius: f32) -> SectionSpec {
    SectionSpec { kinds: [ConduitType::Tube; 2], shape: Shape { radius, ratio: 1.0, asymmetry: 0.0 } }
}

#[test]
fn a_pinched_segment_counts_piece_by_piece_at_its_depth() {
    let (tiny, mut model) = empty();
    // Four 10 m pieces of round sections through half-widths 2, 2, 0.5 (a pinch), 2, 2 m: piece
    // means 2, 1.25, 1.25, 2, so the median of the 40 m is 1.25 m (the segment's mean 1.625,
    // its sections' median 2).
    let radii = [2.0, 2.0, 0.5, 2.0, 2.0];
    for k in 0..4 {
        let mut s = tiny.sweeps[0];
        s.continues = k > 0;
        s.sweep.a = [10.0 * k as f32, 50.0, 50.0];
        s.sweep.b = [10.0 * (k + 1) as f32, 50.0, 50.0];
        s.sweep.start = round(radii[k]);
        s.sweep.end = round(radii[k + 1]);
        model.sweeps.push(s);
    }
    assert!((cave_cell(&model, 4.0, 0.0) - 1.25).abs() < 1e-3, "{}", cave_cell(&model, 4.0, 0.0));
    // Another 30 m segment at 0.75 m: of 70 m, 30 at 0.75 and 20 at 1.25 reach half.
    let mut other = tiny.sweeps[0];
    other.continues = false;
    other.sweep.a = [0.0, 80.0, 50.0];
    other.sweep.b = [30.0, 80.0, 50.0];
    other.sweep.start = round(0.75);
    other.sweep.end = round(0.75);
    model.sweeps.push(other);
    assert!((cave_cell(&model, 4.0, 0.0) - 1.25).abs() < 1e-3, "{}", cave_cell(&model, 4.0, 0.0));
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
