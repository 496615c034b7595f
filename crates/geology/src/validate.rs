//! Scene validation: every problem at once, each with its line and field.
//!
//! Serde reports the first syntax or type error (unknown field, wrong type); [`check`] then
//! reports every semantic problem (NaN, inverted box, a key point above the terrain, a spring
//! without its water table, ...). Lines are found by walking a span-preserving parse of the
//! same text along the field's path.

use crate::spans::{line_of, line_of_path, path_at};
use std::fmt;

use crate::{KeyPointKind, Scene, Surface};

/// One problem in a scene.
#[derive(Debug, Clone, PartialEq)]
pub struct Problem {
    /// 1-based line, when known.
    pub line: Option<usize>,
    /// The field, as a path: `keypoints[2].position`.
    pub field: String,
    pub message: String,
}

impl fmt::Display for Problem {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        if let Some(line) = self.line {
            write!(f, ":{line}")?;
        }
        if self.field.is_empty() {
            write!(f, ": {}", self.message)
        } else {
            write!(f, ": {}: {}", self.field, self.message)
        }
    }
}

/// Turns a TOML parse or type error into a problem with its line and field.
pub(crate) fn from_toml(text: &str, error: &toml::de::Error) -> Problem {
    let span = error.span();
    let line = span.as_ref().map(|s| line_of(text, s.start));
    let field = span.map(|s| path_at(text, s.start)).unwrap_or_default();
    Problem { line, field, message: error.message().trim().to_string() }
}

/// Every semantic problem of a parsed scene.
pub(crate) fn check(scene: &Scene, text: &str) -> Vec<Problem> {
    let mut found = Checks { text, problems: Vec::new() };
    found.domain(scene);
    found.terrain(scene);
    found.surfaces("geology.water_tables", &scene.geology.water_tables, false);
    found.surfaces("geology.horizons", &scene.geology.horizons, false);
    found.surfaces("geology.faults", &scene.geology.faults, true);
    found.fractures(scene);
    found.keypoints(scene);
    found.connectivity(scene);
    found.forced_links(scene);
    found.phases(scene);
    scene.sampling.check(&mut found);
    scene.costgraph.check(&mut found);
    scene.skeleton.check(&mut found);
    scene.sdf.check(&mut found);
    scene.mesher.check(&mut found);
    found.problems
}

pub(crate) struct Checks<'a> {
    text: &'a str,
    problems: Vec<Problem>,
}

impl Checks<'_> {
    pub(crate) fn report(&mut self, field: &str, message: String) {
        let line = line_of_path(self.text, field);
        self.problems.push(Problem { line, field: field.to_string(), message });
    }

    pub(crate) fn finite(&mut self, field: &str, values: &[f64]) -> bool {
        if let Some(v) = values.iter().find(|v| !v.is_finite()) {
            self.report(field, format!("{v} is not a finite number"));
            return false;
        }
        true
    }

    pub(crate) fn positive(&mut self, field: &str, value: f64) {
        if self.finite(field, &[value]) && value <= 0.0 {
            self.report(field, format!("must be > 0, got {value}"));
        }
    }

    pub(crate) fn non_negative(&mut self, field: &str, value: f64) {
        if self.finite(field, &[value]) && value < 0.0 {
            self.report(field, format!("must be ≥ 0, got {value}"));
        }
    }

    fn domain(&mut self, scene: &Scene) {
        let d = &scene.domain;
        if !self.finite("domain.min", &d.min) || !self.finite("domain.max", &d.max) {
            return;
        }
        for (axis, name) in ["x", "y", "z"].iter().enumerate() {
            if d.min[axis] >= d.max[axis] {
                self.report(
                    "domain.max",
                    format!(
                        "inverted box: max.{name} = {} is not above min.{name} = {}",
                        d.max[axis], d.min[axis]
                    ),
                );
            }
        }
    }

    fn terrain(&mut self, scene: &Scene) {
        let crate::Terrain::Plane { elevation, origin, gradient } = &scene.terrain;
        let ok = self.finite("terrain.elevation", &[*elevation])
            & self.finite("terrain.origin", origin)
            & self.finite("terrain.gradient", gradient);
        if ok && self.problems.is_empty() {
            let d = &scene.domain;
            let highest = [d.min[0], d.max[0]]
                .iter()
                .flat_map(|&x| [d.min[1], d.max[1]].map(|y| scene.terrain.height(x, y)))
                .fold(f64::NEG_INFINITY, f64::max);
            if highest <= d.min[2] {
                self.report(
                    "terrain.elevation",
                    format!("the terrain (at most {highest} m) lies below the domain (min z = {}): no bedrock to sample", d.min[2]),
                );
            }
        }
    }

    fn surfaces(&mut self, list: &str, surfaces: &[Surface], vertical_allowed: bool) {
        for (i, s) in surfaces.iter().enumerate() {
            let at = |f: &str| format!("{list}[{i}].{f}");
            self.finite(&at("elevation"), &[s.elevation]);
            self.finite(&at("origin"), &s.origin);
            self.finite(&at("dip_direction"), &[s.dip_direction]);
            let max = if vertical_allowed { "90]" } else { "90)" };
            let ok =
                if vertical_allowed { (0.0..=90.0).contains(&s.dip) } else { (0.0..90.0).contains(&s.dip) };
            if self.finite(&at("dip"), &[s.dip]) && !ok {
                self.report(&at("dip"), format!("must be in [0, {max} degrees, got {}", s.dip));
            }
            if surfaces[..i].iter().any(|o| o.name == s.name) {
                self.report(&at("name"), format!("\"{}\" is used twice", s.name));
            }
        }
    }

    fn fractures(&mut self, scene: &Scene) {
        for (i, f) in scene.geology.fractures.iter().enumerate() {
            let at = |field: &str| format!("geology.fractures[{i}].{field}");
            self.finite(&at("azimuth"), &[f.azimuth]);
            self.non_negative(&at("weight"), f.weight);
            if self.finite(&at("dip"), &[f.dip]) && !(0.0..=90.0).contains(&f.dip) {
                self.report(&at("dip"), format!("must be in [0, 90] degrees, got {}", f.dip));
            }
            if self.finite(&at("tolerance"), &[f.tolerance]) && !(f.tolerance > 0.0 && f.tolerance <= 90.0) {
                self.report(&at("tolerance"), format!("must be in (0, 90] degrees, got {}", f.tolerance));
            }
            if scene.geology.fractures[..i].iter().any(|o| o.name == f.name) {
                self.report(&at("name"), format!("\"{}\" is used twice", f.name));
            }
        }
    }

    fn keypoints(&mut self, scene: &Scene) {
        for (i, k) in scene.keypoints.iter().enumerate() {
            let at = |f: &str| format!("keypoints[{i}].{f}");
            if scene.keypoints[..i].iter().any(|o| o.name == k.name) {
                self.report(&at("name"), format!("\"{}\" is used twice", k.name));
            }
            self.non_negative(&at("weight"), k.weight);
            if self.finite(&at("position"), &k.position) {
                self.keypoint_position(scene, i);
            }
            match (&k.kind, &k.water_table) {
                (KeyPointKind::Spring, None) => {
                    self.report(&at("water_table"), format!("spring \"{}\" names no water table", k.name))
                }
                (KeyPointKind::Spring, Some(w)) if scene.water_table(w).is_none() => self.report(
                    &at("water_table"),
                    format!("spring \"{}\" names water table \"{w}\", which [geology.water_tables] does not define", k.name),
                ),
                (KeyPointKind::Sink | KeyPointKind::Waypoint | KeyPointKind::DeadEnd, Some(_)) => {
                    self.report(&at("water_table"), "only springs have a water table".into())
                }
                _ => {}
            }
        }
        for (kind, name) in [(KeyPointKind::Sink, "sink"), (KeyPointKind::Spring, "spring")] {
            if scene.keypoints_of(kind).next().is_none() {
                self.report("keypoints", format!("the scene needs at least one {name}"));
            }
        }
    }

    fn keypoint_position(&mut self, scene: &Scene, i: usize) {
        let k = &scene.keypoints[i];
        let field = format!("keypoints[{i}].position");
        let [x, y, z] = k.position;
        if !scene.domain.contains(k.point()) {
            self.report(&field, format!("\"{}\" at [{x}, {y}, {z}] is outside the domain", k.name));
            return;
        }
        let ground = scene.terrain.height(x, y);
        if z > ground {
            self.report(
                &field,
                format!("\"{}\" at z = {z} is above the terrain (ground at {ground:.3})", k.name),
            );
        }
    }

    fn phases(&mut self, scene: &Scene) {
        if !scene.phases.is_empty() && scene.skeleton.mode != crate::params::SkeletonMode::Karstnsim {
            self.report("phases", "phases need skeleton.mode = \"karstnsim\"".into());
        }
        let is = |name: &str, kind| scene.keypoints.iter().any(|k| k.name == name && k.kind == kind);
        for (i, phase) in scene.phases.iter().enumerate() {
            let at = |f: &str| format!("phases[{i}].{f}");
            if scene.phases[..i].iter().any(|o| o.name == phase.name) {
                self.report(&at("name"), format!("\"{}\" is used twice", phase.name));
            }
            if phase.springs.is_empty() {
                self.report(&at("springs"), format!("phase \"{}\" lists no spring", phase.name));
            }
            for spring in phase.springs.iter().filter(|s| !is(s, KeyPointKind::Spring)) {
                self.report(
                    &at("springs"),
                    format!("names spring \"{spring}\", which [[keypoints]] does not define"),
                );
            }
            let f = phase.inherited_cost;
            if self.finite(&at("inherited_cost"), &[f]) && !(f > 0.0 && f <= 1.0) {
                self.report(&at("inherited_cost"), format!("must be in (0, 1], got {f}"));
            }
            for (sink, w) in &phase.weights {
                if !is(sink, KeyPointKind::Sink) {
                    self.report(
                        &at("weights"),
                        format!("names sink \"{sink}\", which [[keypoints]] does not define"),
                    );
                } else if !(w.is_finite() && *w >= 0.0) {
                    self.report(&at("weights"), format!("weight of \"{sink}\" must be ≥ 0, got {w}"));
                }
            }
        }
    }

    fn forced_links(&mut self, scene: &Scene) {
        for (i, pair) in scene.skeleton.forced_links.iter().enumerate() {
            let field = format!("skeleton.forced_links[{i}]");
            for name in pair {
                if !scene.keypoints.iter().any(|k| &k.name == name) {
                    self.report(
                        &field,
                        format!("names key point \"{name}\", which [[keypoints]] does not define"),
                    );
                }
            }
            if pair[0] == pair[1] {
                self.report(&field, format!("links \"{}\" to itself", pair[0]));
            }
        }
    }

    fn connectivity(&mut self, scene: &Scene) {
        let Some(rows) = &scene.connectivity.matrix else { return };
        let sinks: Vec<_> = scene.keypoints_of(KeyPointKind::Sink).collect();
        let springs = scene.keypoints_of(KeyPointKind::Spring).count();
        if rows.len() != sinks.len() {
            let msg = format!("has {} rows, the scene has {} sinks", rows.len(), sinks.len());
            self.report("connectivity.matrix", msg);
            return;
        }
        for (r, row) in rows.iter().enumerate() {
            let field = format!("connectivity.matrix[{r}]");
            if row.len() != springs {
                self.report(&field, format!("has {} columns, the scene has {springs} springs", row.len()));
            } else if let Some(v) = row.iter().find(|v| **v > 2) {
                self.report(&field, format!("value {v} is not 0, 1 or 2"));
            } else if row.iter().all(|v| *v == 0) {
                self.report(&field, format!("sink \"{}\" may drain to no spring", sinks[r].1.name));
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use std::path::Path;

    use crate::{Scene, SceneError};

    const GOOD: &str = r#"
name = "t"
seed = 3

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
name = "a"
kind = "sink"
position = [10, 10, 40]

[[keypoints]]
name = "s"
kind = "spring"
position = [90, 90, 10]
water_table = "wt"
"#;

    fn problems(text: &str) -> Vec<String> {
        match Scene::parse(text, Path::new("scene.toml")) {
            Ok(_) => vec![],
            Err(SceneError::Invalid { problems, .. }) => {
                problems.iter().map(|p| format!("scene.toml{p}")).collect()
            }
            Err(e) => panic!("{e}"),
        }
    }

    #[test]
    fn good_scene_parses() {
        assert_eq!(problems(GOOD), Vec::<String>::new());
    }

    #[test]
    fn unknown_field_names_line_and_field() {
        let text = GOOD.replace("seed = 3", "seed = 3\ncolour = \"red\"");
        let p = problems(&text);
        assert_eq!(p.len(), 1);
        assert!(p[0].starts_with("scene.toml:4:"), "{p:?}");
        assert!(p[0].contains("colour"), "{p:?}");
    }

    #[test]
    fn wrong_type_names_the_field() {
        let text = GOOD.replace("elevation = 40", "elevation = \"high\"");
        let p = problems(&text);
        // The terrain is a tagged enum: serde buffers it, so the error points at its table.
        assert!(p[0].contains(":9: terrain: invalid type: string \"high\""), "{p:?}");
    }

    #[test]
    fn every_semantic_problem_is_reported_with_its_line() {
        let text = GOOD
            .replace("max = [100, 100, 50]", "max = [100, -5, 50]")
            .replace("position = [10, 10, 40]", "position = [10, 10, nan]")
            .replace("water_table = \"wt\"", "water_table = \"nope\"");
        let p = problems(&text);
        assert!(p.iter().any(|m| m.contains(":7: domain.max: inverted box")), "{p:?}");
        assert!(p.iter().any(|m| m.contains(":20: keypoints[0].position: NaN")), "{p:?}");
        assert!(p.iter().any(|m| m.contains(":26: keypoints[1].water_table") && m.contains("nope")), "{p:?}");
    }

    #[test]
    fn keypoint_above_terrain_is_refused() {
        let text = GOOD.replace("position = [10, 10, 40]", "position = [10, 10, 45]");
        let p = problems(&text);
        assert!(p[0].contains("above the terrain"), "{p:?}");
    }

    #[test]
    fn connectivity_shape_is_checked() {
        let text = format!("{GOOD}\n[connectivity]\nmatrix = [[1, 1]]\n");
        assert!(problems(&text)[0].contains("2 columns, the scene has 1 springs"));
        let text = format!("{GOOD}\n[connectivity]\nmatrix = [[0]]\n");
        assert!(problems(&text)[0].contains("may drain to no spring"));
    }

    #[test]
    fn section_hash_ignores_other_sections_and_formatting() {
        let a = Scene::parse(GOOD, Path::new("a")).unwrap();
        let b = Scene::parse(&format!("{GOOD}\n[sdf]\nradius_scale = 2\n"), Path::new("b")).unwrap();
        let c =
            Scene::parse(&format!("# comment\n{GOOD}\n[sdf]\nradius_scale = 1.0\n"), Path::new("c")).unwrap();
        assert_eq!(a.sections_hash(&["domain", "sampling"]), b.sections_hash(&["domain", "sampling"]));
        assert_ne!(a.sections_hash(&["sdf"]), b.sections_hash(&["sdf"]));
        assert_eq!(a.sections_hash(&["sdf"]), c.sections_hash(&["sdf"]));
    }
}
