//! Connectivity by name (`[connectivity.named]`): which sink may drain to which spring, written
//! with the key points' names rather than as a matrix in scene order, so that it still reads
//! right when the key points come from a table ([`crate::point_table`]):
//!
//! ```toml
//! [connectivity.named]
//! "Gouffre A" = { "Source S1" = 1, "Source S2" = 0 }   # unlisted pairs are 2 (uncertain)
//! ```
//!
//! When the scene is loaded the table becomes the `matrix` the stages read (one row per sink,
//! one column per spring, scene order); giving both is an error.

use crate::keypoint::keypoints_of;
use crate::{KeyPointKind, Scene};

/// Fills `connectivity.matrix` from `connectivity.named`; problems go to `report(field, message)`.
pub(crate) fn resolve(scene: &mut Scene, report: &mut dyn FnMut(&str, String)) {
    let named = &scene.connectivity.named;
    if named.is_empty() {
        return;
    }
    const FIELD: &str = "connectivity.named";
    if scene.connectivity.matrix.is_some() {
        return report(FIELD, "give the connectivity as `matrix` or as `named`, not both".into());
    }
    let names = |kind| keypoints_of(&scene.keypoints, kind).map(|(_, k)| k.name.as_str()).collect::<Vec<_>>();
    let (sinks, springs) = (names(KeyPointKind::Sink), names(KeyPointKind::Spring));
    let mut matrix = vec![vec![2u8; springs.len()]; sinks.len()];
    let mut ok = true;
    for (sink, row) in named {
        let Some(r) = sinks.iter().position(|s| s == sink) else {
            report(FIELD, format!("\"{sink}\" is not a sink of the scene"));
            ok = false;
            continue;
        };
        for (spring, value) in row {
            match springs.iter().position(|s| s == spring) {
                None => {
                    report(FIELD, format!("\"{sink}\": \"{spring}\" is not a spring of the scene"));
                    ok = false;
                }
                Some(_) if *value > 2 => {
                    report(FIELD, format!("\"{sink}\": \"{spring}\": value {value} is not 0, 1 or 2"));
                    ok = false;
                }
                Some(c) => matrix[r][c] = *value,
            }
        }
    }
    if ok {
        scene.connectivity.matrix = Some(matrix);
    }
}
