//! Scene validation: every problem at once, each with its line and field.
//!
//! Serde reports the first syntax or type error (unknown field, wrong type); [`check`] then
//! reports every semantic problem (NaN, inverted box, a key point above the terrain, a spring
//! without its water table, ...). Lines are found by walking a span-preserving parse of the
//! same text along the field's path.

use crate::spans::{line_of, line_of_path, path_at};
use std::fmt;

use crate::keypoint::keypoints_of;
use karst_geodata::MAX_COORDINATE;
use karst_geology::field::{Bound, FieldKind, FieldNode, Surfaces};
use karst_geology::lithology::Lithology;
use karst_geology::{Geometry, Surface, Terrain};

use crate::{KeyPointKind, Scene};

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

/// "NaN is not a finite number" for the first value that is not finite.
fn not_finite(values: &[f64]) -> Option<String> {
    values.iter().find(|v| !v.is_finite()).map(|v| format!("{v} is not a finite number"))
}

/// Why `value` is not a finite number within `[lo, hi]`, if it is not.
fn outside(value: f64, lo: f64, hi: f64) -> Option<String> {
    not_finite(&[value]).or_else(|| {
        (!(lo..=hi).contains(&value))
            .then(|| format!("must be in [{}, {}], got {}", number(lo), number(hi), number(value)))
    })
}

/// Why `values` are not coordinates (finite, within ±[`MAX_COORDINATE`]), if they are not.
fn beyond_limits(values: &[f64]) -> Option<String> {
    not_finite(values).or_else(|| {
        let v = values.iter().find(|v| v.abs() > MAX_COORDINATE)?;
        Some(format!("{v:e} is beyond ±{MAX_COORDINATE:e} m (docs/limits.md)"))
    })
}

/// Turns a TOML parse or type error into a problem with its line and field.
pub(crate) fn from_toml(text: &str, error: &toml::de::Error) -> Problem {
    let span = error.span();
    let line = span.as_ref().map(|s| line_of(text, s.start));
    let field = span.map(|s| path_at(text, s.start)).unwrap_or_default();
    Problem { line, field, message: error.message().trim().to_string() }
}

/// Arrays written longer than the field holds: serde fills a fixed-size array (a position,
/// a `[min, max]` range) from the first elements and drops the others without a word, so the
/// scene as read is written back and every array compared with the text's.
pub(crate) fn extra_elements(text: &str, scene: &Scene) -> Vec<Problem> {
    let (Ok(given), Ok(read)) = (toml::from_str::<toml::Table>(text), toml::Table::try_from(scene)) else {
        return Vec::new();
    };
    let mut found = Vec::new();
    longer_arrays(&toml::Value::Table(given), &toml::Value::Table(read), String::new(), &mut found);
    found
        .into_iter()
        .map(|(field, given, kept)| Problem {
            line: line_of_path(text, &field),
            message: format!("has {given} elements, but only {kept} are read: remove the others"),
            field,
        })
        .collect()
}

fn longer_arrays(
    given: &toml::Value,
    read: &toml::Value,
    path: String,
    found: &mut Vec<(String, usize, usize)>,
) {
    match (given, read) {
        (toml::Value::Table(g), toml::Value::Table(r)) => {
            for (key, value) in g {
                if let Some(kept) = r.get(key) {
                    let path = if path.is_empty() { key.clone() } else { format!("{path}.{key}") };
                    longer_arrays(value, kept, path, found);
                }
            }
        }
        (toml::Value::Array(g), toml::Value::Array(r)) if g.len() > r.len() => {
            found.push((path, g.len(), r.len()));
        }
        (toml::Value::Array(g), toml::Value::Array(r)) => {
            for (i, (value, kept)) in g.iter().zip(r).enumerate() {
                longer_arrays(value, kept, format!("{path}[{i}]"), found);
            }
        }
        _ => {}
    }
}

/// Every semantic problem of a parsed scene.
pub(crate) fn check(scene: &Scene, text: &str) -> Vec<Problem> {
    let mut found = Checks { text, problems: Vec::new() };
    found.domain(scene);
    let terrain = found.terrain(scene);
    found.surfaces("geology.water_tables", &scene.geology.water_tables, false);
    found.surfaces("geology.horizons", &scene.geology.horizons, false);
    found.surfaces("geology.faults", &scene.geology.faults, true);
    found.fractures(scene);
    found.layers(scene);
    found.field_nodes(scene, "geology.potential", &scene.geology.potential, false);
    found.field_nodes(scene, "geology.no_karst", &scene.geology.no_karst, true);
    if let Some(lithology) = &scene.geology.lithology {
        found.lithology(lithology);
    }
    found.keypoints(scene, terrain);
    found.connectivity(scene);
    found.forced_links(scene);
    found.phases(scene);
    scene.sampling.check(&mut found);
    scene.costgraph.check(&mut found);
    scene.skeleton.check(&mut found);
    found.amplification(scene);
    scene.hydro.check(&mut found);
    scene.streams.check(scene, &mut found);
    scene.sdf.check(&mut found);
    scene.mesher.check(&mut found);
    scene.export.check(&mut found);
    if let Some(calibrate) = &scene.calibrate {
        calibrate.check(scene, &mut found);
    }
    found.problems
}

/// A number as people write it: plain when moderate, in exponent notation when huge or tiny.
fn number(v: f64) -> String {
    if v != 0.0 && !(1e-4..1e6).contains(&v.abs()) { format!("{v:e}") } else { format!("{v}") }
}

/// Largest extent of the domain along an axis, metres.
pub const MAX_EXTENT: f64 = 1e6;
/// Largest length, distance, weight or factor without a range of its own.
pub const MAX_LENGTH: f64 = 1e8;
/// Shortest length a `[min, max]` range of lengths (branch lengths, wavelengths) may start at,
/// metres.
pub const MIN_LENGTH: f64 = 1e-3;
/// Most key points in a scene.
pub const MAX_KEYPOINTS: usize = 10_000;
/// Steepest terrain slope λ (|∇h|): the terrain's distance is (z − h)/√(1 + λ²), which
/// vanishes when λ does not stay finite and reasonable.
pub const MAX_TERRAIN_SLOPE: f64 = 1e4;
/// Largest sink weight (relative recharge).
pub const MAX_WEIGHT: f64 = 1e9;

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
        match not_finite(values) {
            Some(message) => {
                self.report(field, message);
                false
            }
            None => true,
        }
    }

    /// Finite, > 0 and at most [`MAX_LENGTH`] (every length, weight and factor without a
    /// tighter range of its own).
    pub(crate) fn positive(&mut self, field: &str, value: f64) {
        if self.finite(field, &[value]) && value <= 0.0 {
            self.report(field, format!("must be > 0, got {value}"));
        } else {
            self.at_most(field, value, MAX_LENGTH);
        }
    }

    /// Finite, ≥ 0 and at most [`MAX_LENGTH`].
    pub(crate) fn non_negative(&mut self, field: &str, value: f64) {
        if self.finite(field, &[value]) && value < 0.0 {
            self.report(field, format!("must be ≥ 0, got {value}"));
        } else {
            self.at_most(field, value, MAX_LENGTH);
        }
    }

    /// Amplification branches shorter than the sampling radius could not be drawn: the
    /// samples are that far apart.
    fn amplification(&mut self, scene: &Scene) {
        let Some(radius) = scene.sampling.radius.map(|r| r * scene.sampling.unit_scale(&scene.domain)) else {
            return;
        };
        if let Some([lo, _]) = scene.skeleton.amplification_length
            && lo.is_finite()
            && radius.is_finite()
            && lo < radius
        {
            self.report(
                "skeleton.amplification_length",
                format!("the shortest branch ({lo} m) must be at least sampling.radius ({radius} m)"),
            );
        }
    }

    fn at_most(&mut self, field: &str, value: f64, most: f64) {
        if value > most {
            self.report(field, format!("must be at most {most:e}, got {value:e} (docs/limits.md)"));
        }
    }

    /// Finite and within `[lo, hi]`; returns whether it is.
    pub(crate) fn within(&mut self, field: &str, value: f64, lo: f64, hi: f64) -> bool {
        self.holds(field, outside(value, lo, hi))
    }

    /// Reports `problem` at `field` if there is one; returns whether there was none.
    fn holds(&mut self, field: &str, problem: Option<String>) -> bool {
        match problem {
            Some(message) => {
                self.report(field, message);
                false
            }
            None => true,
        }
    }

    /// A `[min, max]` range whose ends are within `[lo, hi]`, min ≤ max.
    pub(crate) fn range(&mut self, field: &str, [min, max]: [f64; 2], lo: f64, hi: f64) {
        if self.within(field, min, lo, hi) & self.within(field, max, lo, hi) && max < min {
            self.report(field, format!("[{min}, {max}] is not a range (max < min)"));
        }
    }

    /// Coordinates: finite and within ±[`MAX_COORDINATE`].
    pub(crate) fn coordinates(&mut self, field: &str, values: &[f64]) -> bool {
        self.holds(field, beyond_limits(values))
    }

    fn domain(&mut self, scene: &Scene) {
        let d = &scene.domain;
        if !self.coordinates("domain.min", &d.min) | !self.coordinates("domain.max", &d.max) {
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
            } else if d.max[axis] - d.min[axis] > MAX_EXTENT {
                let extent = d.max[axis] - d.min[axis];
                self.report(
                    "domain.max",
                    format!("the domain is {extent:e} m along {name}, more than {MAX_EXTENT:e} m"),
                );
            }
        }
    }

    /// Checks the terrain; true when it can be evaluated.
    fn terrain(&mut self, scene: &Scene) -> bool {
        let ok = match &scene.terrain {
            Terrain::Plane { elevation, origin, gradient } => {
                self.coordinates("terrain.elevation", &[*elevation])
                    & self.coordinates("terrain.origin", origin)
                    & self.within("terrain.gradient", gradient[0].hypot(gradient[1]), 0.0, MAX_TERRAIN_SLOPE)
            }
            Terrain::Heightfield { origin, cell_size, vertical_scale, offset, grid, .. } => {
                let ok = origin.is_none_or(|o| self.coordinates("terrain.origin", &o))
                    & self.within("terrain.vertical_scale", *vertical_scale, -MAX_LENGTH, MAX_LENGTH)
                    & self.coordinates("terrain.offset", &[*offset]);
                if let Some(c) = cell_size {
                    self.positive("terrain.cell_size", *c);
                }
                ok && cell_size.is_none_or(|c| c > 0.0) && grid.nx > 0 && self.heightfield_covers(scene, grid)
            }
            Terrain::Noise { elevation, amplitude, wavelength, octaves, gradient, .. } => {
                let ok = self.coordinates("terrain.elevation", &[*elevation])
                    & self.within("terrain.amplitude", *amplitude, -MAX_LENGTH, MAX_LENGTH)
                    & self.within("terrain.gradient", gradient[0].hypot(gradient[1]), 0.0, MAX_TERRAIN_SLOPE)
                    & self.within(
                        "terrain.octaves",
                        *octaves as f64,
                        0.0,
                        karst_geology::terrain::MAX_OCTAVES as f64,
                    );
                self.positive("terrain.wavelength", *wavelength);
                ok && *wavelength > 0.0
            }
        };
        // A derived quantity, checked where it is made: the steepest slope of the ground.
        let lambda = scene.terrain.lipschitz();
        if ok && (lambda.is_nan() || lambda > MAX_TERRAIN_SLOPE) {
            let driver = match scene.terrain {
                Terrain::Noise { .. } => "terrain.wavelength",
                Terrain::Heightfield { .. } => "terrain.cell_size",
                Terrain::Plane { .. } => "terrain.gradient",
            };
            self.report(
                driver,
                format!("gives the terrain a steepest slope of {lambda:e} (at most {MAX_TERRAIN_SLOPE:e}): the terrain would be a wall"),
            );
            return false;
        }
        if ok && self.problems.is_empty() {
            let d = &scene.domain;
            let highest = [d.min[0], d.max[0]]
                .iter()
                .flat_map(|&x| [d.min[1], d.max[1]].map(|y| scene.terrain.height(x, y)))
                .fold(f64::NEG_INFINITY, f64::max)
                .max(scene.terrain.height(d.centre().x, d.centre().y));
            if highest <= d.min[2] {
                self.report(
                    "terrain",
                    format!("the terrain (at most {highest} m) lies below the domain (min z = {}): no bedrock to sample", d.min[2]),
                );
            }
        }
        ok
    }

    fn heightfield_covers(&mut self, scene: &Scene, grid: &karst_geology::heightfield::HeightGrid) -> bool {
        let d = &scene.domain;
        let [ex, ey] = grid.extent();
        if ex[0] > d.min[0] || ex[1] < d.max[0] || ey[0] > d.min[1] || ey[1] < d.max[1] {
            self.report(
                "terrain.file",
                format!(
                    "the heightfield covers x [{}, {}], y [{}, {}], not the domain's x [{}, {}], y [{}, {}]",
                    ex[0], ex[1], ey[0], ey[1], d.min[0], d.max[0], d.min[1], d.max[1]
                ),
            );
            return false;
        }
        if let Some((i, j)) = grid.first_hole([d.min[0], d.max[0]], [d.min[1], d.max[1]]) {
            self.report(
                "terrain.nodata",
                format!("pixel (column {i}, row {}) inside the domain has no data", grid.ny as usize - 1 - j),
            );
            return false;
        }
        true
    }

    fn surfaces(&mut self, list: &str, surfaces: &[Surface], vertical_allowed: bool) {
        for (i, s) in surfaces.iter().enumerate() {
            let at = |f: &str| format!("{list}[{i}].{f}");
            if let Geometry::Plane { elevation, origin, dip, dip_direction, .. } = &s.geometry {
                self.coordinates(&at("elevation"), &[*elevation]);
                self.coordinates(&at("origin"), origin);
                self.within(&at("dip_direction"), *dip_direction, -360.0, 360.0);
                let max = if vertical_allowed { "90]" } else { "90)" };
                let ok =
                    if vertical_allowed { (0.0..=90.0).contains(dip) } else { (0.0..90.0).contains(dip) };
                if self.finite(&at("dip"), &[*dip]) && !ok {
                    self.report(&at("dip"), format!("must be in [0, {max} degrees, got {dip}"));
                }
            }
            if surfaces[..i].iter().any(|o| o.name == s.name) {
                self.report(&at("name"), format!("\"{}\" is used twice", s.name));
            }
        }
    }

    fn bound(&mut self, scene: &Scene, field: &str, bound: &Bound) {
        match bound {
            Bound::Elevation(z) => {
                self.coordinates(field, &[*z]);
            }
            Bound::Surface(name) => {
                if scene.geology.surface(name).is_none() {
                    self.report(
                        field,
                        format!("\"{name}\" is not a horizon, fault or water table of [geology]"),
                    );
                }
            }
        }
    }

    fn layers(&mut self, scene: &Scene) {
        for (i, l) in scene.geology.layers.iter().enumerate() {
            let at = |f: &str| format!("geology.layers[{i}].{f}");
            for (f, b) in [("top", &l.top), ("bottom", &l.bottom)] {
                if let Some(b) = b {
                    self.bound(scene, &at(f), b);
                }
            }
            self.unit_interval(&at("potential"), l.potential);
            if let Some(r) = l.radius {
                self.positive(&at("radius"), r);
            }
            if scene.geology.layers[..i].iter().any(|o| o.name == l.name) {
                self.report(&at("name"), format!("\"{}\" is used twice", l.name));
            }
        }
    }

    fn unit_interval(&mut self, field: &str, v: f64) {
        if self.finite(field, &[v]) && !(0.0..=1.0).contains(&v) {
            self.report(field, format!("must be in [0, 1], got {v}"));
        }
    }

    fn field_nodes(&mut self, scene: &Scene, list: &str, nodes: &[FieldNode], primitives_only: bool) {
        for (i, n) in nodes.iter().enumerate() {
            let at = |f: &str| format!("{list}[{i}].{f}");
            if nodes[..i].iter().any(|o| o.name == n.name) {
                self.report(&at("name"), format!("\"{}\" is used twice", n.name));
            }
            if primitives_only && n.shape().is_none() && n.missing().is_empty() {
                self.report(&at("kind"), format!("{:?} is not a volume: use sphere, box or stratum", n.kind));
                continue;
            }
            for f in n.missing() {
                self.report(&at(f), format!("{:?} \"{}\" needs `{f}`", n.kind, n.name));
            }
            for (f, v) in [("centre", n.centre), ("min", n.min), ("max", n.max)] {
                if let Some(v) = v {
                    self.coordinates(&at(f), &v);
                }
            }
            if let Some(r) = n.radius {
                self.positive(&at("radius"), r);
            }
            for (f, b) in [("top", &n.top), ("bottom", &n.bottom)] {
                if let Some(b) = b {
                    self.bound(scene, &at(f), b);
                }
            }
            if !primitives_only {
                self.unit_interval(&at("inside"), n.inside);
                self.unit_interval(&at("outside"), n.outside);
                self.non_negative(&at("falloff"), n.falloff);
            }
            for child in &n.of {
                if !nodes[..i].iter().any(|o| &o.name == child) {
                    self.report(&at("of"), format!("\"{child}\" is not an earlier node of {list}"));
                }
            }
            if n.kind == FieldKind::Blend && !n.weights.is_empty() {
                if n.weights.len() != n.of.len() {
                    self.report(
                        &at("weights"),
                        format!("has {} weights for {} children", n.weights.len(), n.of.len()),
                    );
                } else if self.finite(&at("weights"), &n.weights)
                    && (n.weights.iter().any(|w| !(0.0..=MAX_WEIGHT).contains(w))
                        || n.weights.iter().sum::<f64>() <= 0.0)
                {
                    self.report(&at("weights"), format!("{:?} must be ≥ 0 and not all 0", n.weights));
                }
            }
        }
    }

    /// `[geology.lithology]`: the units' own fields.
    fn lithology(&mut self, lithology: &Lithology) {
        for (i, u) in lithology.units.iter().enumerate() {
            let at = |f: &str| format!("geology.lithology.units[{i}].{f}");
            if self.finite(&at("potential"), &[u.potential]) && !(0.0..=1.0).contains(&u.potential) {
                self.report(&at("potential"), format!("must be in [0, 1], got {}", u.potential));
            }
            if let Some(r) = u.radius {
                self.positive(&at("radius"), r);
            }
            if lithology.units[..i].iter().any(|o| o.code == u.code) {
                self.report(&at("code"), format!("code {} is mapped twice", u.code));
            }
            if lithology.units[..i].iter().any(|o| o.name == u.name) {
                self.report(&at("name"), format!("\"{}\" is used twice", u.name));
            }
        }
        if let Some(s) = lithology.spacing
            && self.finite("geology.lithology.spacing", &s)
            && s.iter().any(|v| *v <= 0.0)
        {
            self.report("geology.lithology.spacing", format!("must be > 0, got {s:?}"));
        }
        if let Some(o) = lithology.origin {
            self.finite("geology.lithology.origin", &o);
        }
    }

    fn fractures(&mut self, scene: &Scene) {
        for (i, f) in scene.geology.fractures.iter().enumerate() {
            let at = |field: &str| format!("geology.fractures[{i}].{field}");
            self.within(&at("azimuth"), f.azimuth, -360.0, 360.0);
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

    /// Reports `message` about field `f` of key point `i`: at `keypoints[i].f`, or, for a point
    /// read from a table, at the table's `keypoints_from[t].file` with the file's row and column.
    fn keypoint(&mut self, scene: &Scene, i: usize, f: &str, message: String) {
        match crate::point_table::source_of(scene, i) {
            None => self.report(&format!("keypoints[{i}].{f}"), message),
            Some((t, row)) => {
                let column = if f == "position" { "x, y, z" } else { f };
                self.report(&format!("keypoints_from[{t}].file"), format!("{row}: {column}: {message}"))
            }
        }
    }

    fn keypoints(&mut self, scene: &Scene, terrain: bool) {
        for (i, k) in scene.keypoints.iter().enumerate() {
            if scene.keypoints[..i].iter().any(|o| o.name == k.name) {
                self.keypoint(scene, i, "name", format!("\"{}\" is used twice", k.name));
            }
            if let Some(message) = outside(k.weight, 0.0, MAX_WEIGHT) {
                self.keypoint(scene, i, "weight", message);
            }
            match beyond_limits(&k.position) {
                Some(message) => self.keypoint(scene, i, "position", message),
                None => {
                    self.keypoint_position(scene, i, terrain);
                    if let Some(o) = scene.keypoints[..i].iter().find(|o| o.position == k.position) {
                        let message = format!(
                            "\"{}\" lies where \"{}\" does, {:?}: two key points need two places",
                            k.name, o.name, k.position
                        );
                        self.keypoint(scene, i, "position", message);
                    }
                }
            }
            match (&k.kind, &k.water_table) {
                (KeyPointKind::Spring, None) => {
                    self.keypoint(scene, i, "water_table", format!("spring \"{}\" names no water table", k.name))
                }
                (KeyPointKind::Spring, Some(w)) if scene.geology.water_table(w).is_none() => self.keypoint(
                    scene,
                    i,
                    "water_table",
                    format!("spring \"{}\" names water table \"{w}\", which [geology.water_tables] does not define", k.name),
                ),
                (KeyPointKind::Sink | KeyPointKind::Waypoint | KeyPointKind::DeadEnd, Some(_)) => {
                    self.keypoint(scene, i, "water_table", "only springs have a water table".into())
                }
                _ => {}
            }
        }
        if scene.keypoints.len() > MAX_KEYPOINTS {
            self.report(
                "keypoints",
                format!("has {} key points, at most {MAX_KEYPOINTS}", scene.keypoints.len()),
            );
        }
        for (kind, name) in [(KeyPointKind::Sink, "sink"), (KeyPointKind::Spring, "spring")] {
            if keypoints_of(&scene.keypoints, kind).next().is_none() {
                self.report("keypoints", format!("the scene needs at least one {name}"));
            }
        }
    }

    fn keypoint_position(&mut self, scene: &Scene, i: usize, terrain: bool) {
        let k = &scene.keypoints[i];
        let [x, y, z] = k.position;
        if !scene.domain.contains(k.point()) {
            self.keypoint(
                scene,
                i,
                "position",
                format!("\"{}\" at [{x}, {y}, {z}] is outside the domain", k.name),
            );
            return;
        }
        if let Some(v) = scene
            .geology
            .no_karst
            .iter()
            .find(|v| v.shape().is_some_and(|s| s.signed_distance(k.point(), &scene.geology) <= 0.0))
        {
            let message =
                format!("\"{}\" at [{x}, {y}, {z}] is inside no-karst volume \"{}\"", k.name, v.name);
            self.keypoint(scene, i, "position", message);
        }
        if let Some(unit) = scene.geology.lithology.as_ref().and_then(|l| l.grid.no_karst_at(k.point())) {
            let message =
                format!("\"{}\" at [{x}, {y}, {z}] is in no-karst lithology unit \"{unit}\"", k.name);
            self.keypoint(scene, i, "position", message);
        }
        let ground = if terrain { scene.terrain.height(x, y) } else { f64::INFINITY };
        if z > ground {
            let message = format!("\"{}\" at z = {z} is above the terrain (ground at {ground:.3})", k.name);
            self.keypoint(scene, i, "position", message);
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
                } else if !(0.0..=MAX_WEIGHT).contains(w) {
                    self.report(
                        &at("weights"),
                        format!("weight of \"{sink}\" must be in [0, {MAX_WEIGHT:e}], got {w}"),
                    );
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
        let sinks: Vec<_> = keypoints_of(&scene.keypoints, KeyPointKind::Sink).collect();
        let springs = keypoints_of(&scene.keypoints, KeyPointKind::Spring).count();
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

    use crate::{Scene, SceneError, Section};

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
    fn extra_array_elements_are_refused() {
        let text = GOOD.replace("max = [100, 100, 50]", "max = [100, 100, 50, -999, 7]");
        let p = problems(&text);
        assert!(p.iter().any(|m| m.contains(":7: domain.max: has 5 elements, but only 3 are read")), "{p:?}");
        let text = format!("{GOOD}\n[skeleton]\nradius = [2, 3, 4]\n");
        let p = problems(&text);
        assert!(p.iter().any(|m| m.contains("skeleton.radius: has 3 elements, but only 2")), "{p:?}");
        let text = GOOD.replace("position = [90, 90, 10]", "position = [90, 90, 10, 4]");
        assert!(problems(&text).iter().any(|m| m.contains("keypoints[1].position: has 4 elements")));
    }

    #[test]
    fn upper_bounds_and_derived_quantities_are_checked() {
        let p = problems(&format!("{GOOD}\n[skeleton]\nradius = [1, nan]\nradius_correlation = [1, inf]\n"));
        assert!(p.iter().any(|m| m.contains("skeleton.radius: NaN is not a finite number")), "{p:?}");
        assert!(
            p.iter().any(|m| m.contains("skeleton.radius_correlation: inf is not a finite number")),
            "{p:?}"
        );
        let p = problems(
            &GOOD.replace("name = \"a\"\nkind = \"sink\"", "name = \"a\"\nkind = \"sink\"\nweight = 1e308"),
        );
        assert!(p.iter().any(|m| m.contains("keypoints[0].weight: must be in [0, 1e9], got 1e308")), "{p:?}");
        let p = problems(&format!("{GOOD}\n[costgraph]\ncost_floor = 1e300\n"));
        assert!(p.iter().any(|m| m.contains("costgraph.cost_floor: must be in")), "{p:?}");
        let noise = "kind = \"noise\"\nelevation = 40\namplitude = 5\nwavelength = 1e-154";
        let p = problems(&GOOD.replace("kind = \"plane\"\nelevation = 40", noise));
        assert!(
            p.iter().any(|m| m.contains("terrain.wavelength: gives the terrain a steepest slope")),
            "{p:?}"
        );
        let p = problems(&GOOD.replace("max = [100, 100, 50]", "max = [1e308, 100, 50]"));
        assert!(p.iter().any(|m| m.contains("domain.max: 1e308 is beyond")), "{p:?}");
    }

    #[test]
    fn coincident_key_points_are_named() {
        let text = GOOD.replace("position = [90, 90, 10]", "position = [10, 10, 40]");
        let p = problems(&text);
        assert!(p.iter().any(|m| m.contains("keypoints[1].position: \"s\" lies where \"a\" does")), "{p:?}");
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
    fn geology_model_fields_are_validated_and_evaluated() {
        let model = r#"
[[geology.layers]]
name = "marl"
top = "bed"
potential = 0.25

[[geology.potential]]
name = "lens"
kind = "sphere"
centre = [50, 50, 30]
radius = 5
outside = 0.5

[[geology.no_karst]]
name = "dyke"
kind = "box"
min = [0, 0, 0]
max = [5, 100, 50]
"#;
        let text = format!("{GOOD}\n[[geology.horizons]]\nname = \"bed\"\nelevation = 20\n{model}");
        let scene = Scene::parse(&text, Path::new("s.toml")).unwrap();
        let g = &scene.geology;
        assert_eq!(g.potential(karst_geology::Point::new(50.0, 50.0, 30.0)), 1.0);
        assert_eq!(g.potential(karst_geology::Point::new(80.0, 50.0, 30.0)), 0.5);
        assert_eq!(g.potential(karst_geology::Point::new(80.0, 50.0, 10.0)), 0.25 * 0.5);
        assert!(g.in_no_karst(karst_geology::Point::new(2.0, 50.0, 10.0)));
        assert!(!g.in_no_karst(karst_geology::Point::new(6.0, 50.0, 10.0)));
        let bad = text
            .replace("top = \"bed\"", "top = \"nope\"")
            .replace("radius = 5", "radius = -5")
            .replace("potential = 0.25", "potential = 1.5")
            .replace("position = [10, 10, 40]", "position = [2, 10, 40]");
        let p = problems(&bad);
        assert!(p.iter().any(|m| m.contains("geology.layers[0].top: \"nope\" is not a horizon")), "{p:?}");
        assert!(
            p.iter().any(|m| m.contains("geology.layers[0].potential: must be in [0, 1], got 1.5")),
            "{p:?}"
        );
        assert!(p.iter().any(|m| m.contains("geology.potential[0].radius: must be > 0, got -5")), "{p:?}");
        assert!(p.iter().any(|m| m.contains("inside no-karst volume \"dyke\"")), "{p:?}");
        let tree = text.replace("[[geology.no_karst]]", "[[geology.potential]]\nname = \"top\"\nkind = \"max\"\nof = [\"lens\", \"ghost\"]\n\n[[geology.no_karst]]");
        assert!(problems(&tree).iter().any(|m| m.contains("\"ghost\" is not an earlier node")));
    }

    #[test]
    fn section_hash_ignores_other_sections_and_formatting() {
        let a = Scene::parse(GOOD, Path::new("a")).unwrap();
        let b = Scene::parse(&format!("{GOOD}\n[sdf]\nradius_scale = 2\n"), Path::new("b")).unwrap();
        let c =
            Scene::parse(&format!("# comment\n{GOOD}\n[sdf]\nradius_scale = 1.0\n"), Path::new("c")).unwrap();
        assert_eq!(
            a.sections_hash(&[Section::Domain, Section::Sampling]),
            b.sections_hash(&[Section::Domain, Section::Sampling])
        );
        assert_ne!(a.sections_hash(&[Section::Sdf]), b.sections_hash(&[Section::Sdf]));
        assert_eq!(a.sections_hash(&[Section::Sdf]), c.sections_hash(&[Section::Sdf]));
    }
}
