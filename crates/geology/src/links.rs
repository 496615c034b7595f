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
    let names = |kind| scene.keypoints_of(kind).map(|(_, k)| k.name.as_str()).collect::<Vec<_>>();
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

#[cfg(test)]
mod tests {
    use std::path::Path;

    use crate::{Link, Scene, SceneError};

    const SCENE: &str = r#"
name = "t"
[domain]
min = [0, 0, 0]
max = [100, 100, 50]
[terrain]
kind = "plane"
elevation = 40
[[geology.water_tables]]
name = "wt"
elevation = 10
[[keypoints]]
name = "A"
kind = "sink"
position = [10, 10, 40]
[[keypoints]]
name = "B"
kind = "sink"
position = [20, 10, 40]
[[keypoints]]
name = "S1"
kind = "spring"
position = [90, 90, 10]
water_table = "wt"
[[keypoints]]
name = "S2"
kind = "spring"
position = [90, 10, 10]
water_table = "wt"
"#;

    #[test]
    fn names_become_the_matrix() {
        let text = format!("{SCENE}[connectivity.named]\nA = {{ S1 = 1, S2 = 0 }}\n");
        let scene = Scene::parse(&text, Path::new("s.toml")).unwrap();
        assert_eq!(scene.connectivity.matrix, Some(vec![vec![1, 0], vec![2, 2]]));
        assert_eq!(scene.link(0, 1), Link::None);
        assert_eq!(scene.link(1, 0), Link::Uncertain);
    }

    #[test]
    fn unknown_names_values_and_both_forms_are_refused() {
        let problems = |extra: &str| match Scene::parse(&format!("{SCENE}{extra}"), Path::new("s.toml")) {
            Err(SceneError::Invalid { problems, .. }) => {
                problems.iter().map(|p| p.to_string()).collect::<Vec<_>>()
            }
            other => panic!("{other:?}"),
        };
        let p = problems("[connectivity.named]\nZ = { S1 = 1 }\nA = { S9 = 1, S2 = 3 }\n");
        assert!(p.iter().any(|m| m.contains(":30: connectivity.named: \"Z\" is not a sink")), "{p:?}");
        assert!(p.iter().any(|m| m.contains("\"A\": \"S9\" is not a spring")), "{p:?}");
        assert!(p.iter().any(|m| m.contains("\"A\": \"S2\": value 3 is not 0, 1 or 2")), "{p:?}");
        let p = problems("[connectivity]\nmatrix = [[1, 1], [1, 1]]\nnamed = { A = { S1 = 0 } }\n");
        assert!(p.iter().any(|m| m.contains("not both")), "{p:?}");
        let p = problems("[connectivity.named]\nA = { S1 = 0, S2 = 0 }\n");
        assert!(p.iter().any(|m| m.contains("sink \"A\" may drain to no spring")), "{p:?}");
    }
}
