//! Scene validation: every problem at once, each with its line and field.
//!
//! Serde reports the first syntax or type error (unknown field, wrong type); [`check`] then
//! reports every semantic problem (NaN, inverted box, a key point above the terrain, a spring
//! without its water table, ...). Lines are found by walking a span-preserving parse of the
//! same text along the field's path.

use std::fmt;
use std::ops::Range;

use toml::Spanned;
use toml::de::{DeTable, DeValue};

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
    found.surfaces("geology.water_tables", &scene.geology.water_tables);
    found.surfaces("geology.horizons", &scene.geology.horizons);
    found.keypoints(scene);
    found.connectivity(scene);
    found.params(scene);
    found.problems
}

struct Checks<'a> {
    text: &'a str,
    problems: Vec<Problem>,
}

impl Checks<'_> {
    fn report(&mut self, field: &str, message: String) {
        let line = line_of_path(self.text, field);
        self.problems.push(Problem { line, field: field.to_string(), message });
    }

    fn finite(&mut self, field: &str, values: &[f64]) -> bool {
        if let Some(v) = values.iter().find(|v| !v.is_finite()) {
            self.report(field, format!("{v} is not a finite number"));
            return false;
        }
        true
    }

    fn positive(&mut self, field: &str, value: f64) {
        if self.finite(field, &[value]) && value <= 0.0 {
            self.report(field, format!("must be > 0, got {value}"));
        }
    }

    fn non_negative(&mut self, field: &str, value: f64) {
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
                    format!("inverted box: max.{name} = {} is not above min.{name} = {}", d.max[axis], d.min[axis]),
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

    fn surfaces(&mut self, list: &str, surfaces: &[Surface]) {
        for (i, s) in surfaces.iter().enumerate() {
            let at = |f: &str| format!("{list}[{i}].{f}");
            self.finite(&at("elevation"), &[s.elevation]);
            self.finite(&at("origin"), &s.origin);
            self.finite(&at("dip_direction"), &[s.dip_direction]);
            if self.finite(&at("dip"), &[s.dip]) && !(0.0..90.0).contains(&s.dip) {
                self.report(&at("dip"), format!("must be in [0, 90) degrees, got {}", s.dip));
            }
            if surfaces[..i].iter().any(|o| o.name == s.name) {
                self.report(&at("name"), format!("\"{}\" is used twice", s.name));
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
                (KeyPointKind::Sink | KeyPointKind::Waypoint, Some(_)) => {
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
            self.report(&field, format!("\"{}\" at z = {z} is above the terrain (ground at {ground:.3})", k.name));
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

    fn params(&mut self, scene: &Scene) {
        self.positive("sampling.radius", scene.sampling.radius);
        if scene.sampling.attempts == 0 {
            self.report("sampling.attempts", "must be ≥ 1".into());
        }
        let c = &scene.costgraph;
        if c.k == 0 {
            self.report("costgraph.k", "must be ≥ 1".into());
        }
        if let Some(l) = c.max_edge_length {
            self.positive("costgraph.max_edge_length", l);
        }
        self.non_negative("costgraph.horizon_weight", c.horizon_weight);
        self.positive("costgraph.horizon_distance", c.horizon_distance);
        self.non_negative("costgraph.phreatic_weight", c.phreatic_weight);
        self.positive("costgraph.phreatic_distance", c.phreatic_distance);
        let [lo, hi] = scene.skeleton.radius;
        self.positive("skeleton.radius", lo);
        if lo.is_finite() && hi.is_finite() && hi < lo {
            self.report("skeleton.radius", format!("[{lo}, {hi}] is not a range (max < min)"));
        }
        self.positive("sdf.radius_scale", scene.sdf.radius_scale);
        self.positive("mesher.cell_size", scene.mesher.cell_size);
    }
}

/// 1-based line of byte `offset`.
fn line_of(text: &str, offset: usize) -> usize {
    text[..offset.min(text.len())].bytes().filter(|b| *b == b'\n').count() + 1
}

/// Line where the field at `path` (`keypoints[2].position`) is written, if it is written.
fn line_of_path(text: &str, path: &str) -> Option<usize> {
    let root = DeTable::parse(text).ok()?;
    let mut span = root.span();
    let mut value: Option<&DeValue> = None;
    let mut table = Some(root.get_ref());
    for segment in parse_path(path) {
        let next: &Spanned<DeValue> = match segment {
            Segment::Key(key) => table?.iter().find(|(k, _)| k.get_ref() == key).map(|(_, v)| v)?,
            Segment::Index(i) => match value? {
                DeValue::Array(items) => items.get(i)?,
                _ => return None,
            },
        };
        span = next.span();
        value = Some(next.get_ref());
        table = match next.get_ref() {
            DeValue::Table(t) => Some(t),
            _ => None,
        };
    }
    Some(line_of(text, span.start))
}

/// Path of the innermost field whose key or value contains byte `offset`. Header tables
/// (`[costgraph]`, `[[keypoints]]`) do not span their contents, so every child is searched.
fn path_at(text: &str, offset: usize) -> String {
    let Ok(root) = DeTable::parse(text) else { return String::new() };
    search_table(root.get_ref(), offset).unwrap_or_default()
}

fn search_table(table: &DeTable, offset: usize) -> Option<String> {
    table.iter().find_map(|(key, value)| {
        let name = key.get_ref().to_string();
        match search_value(value, offset) {
            Some(rest) if rest.is_empty() => Some(name),
            Some(rest) if rest.starts_with('[') => Some(format!("{name}{rest}")),
            Some(rest) => Some(format!("{name}.{rest}")),
            None if contains(&key.span(), offset) => Some(name),
            None => None,
        }
    })
}

/// Some(path below this value) when `offset` is inside it ("" for the value itself).
fn search_value(value: &Spanned<DeValue>, offset: usize) -> Option<String> {
    match value.get_ref() {
        DeValue::Table(t) => search_table(t, offset),
        DeValue::Array(items) => items.iter().enumerate().find_map(|(i, item)| {
            search_value(item, offset).map(|rest| match rest.as_str() {
                "" => format!("[{i}]"),
                r if r.starts_with('[') => format!("[{i}]{r}"),
                r => format!("[{i}].{r}"),
            })
        }),
        _ => contains(&value.span(), offset).then(String::new),
    }
    .or_else(|| contains(&value.span(), offset).then(String::new))
}

fn contains(span: &Range<usize>, offset: usize) -> bool {
    span.start <= offset && offset < span.end.max(span.start + 1)
}

enum Segment<'a> {
    Key(&'a str),
    Index(usize),
}

fn parse_path(path: &str) -> Vec<Segment<'_>> {
    let mut segments = Vec::new();
    for part in path.split('.') {
        let (key, rest) = part.split_once('[').unwrap_or((part, ""));
        segments.push(Segment::Key(key));
        for index in rest.split('[') {
            if let Ok(i) = index.trim_end_matches(']').parse() {
                segments.push(Segment::Index(i));
            }
        }
    }
    segments
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
            Err(SceneError::Invalid { problems, .. }) => problems.iter().map(|p| format!("scene.toml{p}")).collect(),
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
        let c = Scene::parse(&format!("# comment\n{GOOD}\n[sdf]\nradius_scale = 1.0\n"), Path::new("c")).unwrap();
        assert_eq!(a.sections_hash(&["domain", "sampling"]), b.sections_hash(&["domain", "sampling"]));
        assert_ne!(a.sections_hash(&["sdf"]), b.sections_hash(&["sdf"]));
        assert_eq!(a.sections_hash(&["sdf"]), c.sections_hash(&["sdf"]));
    }
}
