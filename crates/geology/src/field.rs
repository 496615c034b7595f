//! Fields over the volume: the karstification potential P(p) ∈ [0, 1] (KarstNSim §1.1: 1 is
//! the most karstifiable rock; Paris et al. 2021 §3's relative resistance to flow is 1 − P),
//! the layers (KarstNSim Table 1: limestone, marl, granite, each with its potential and
//! sampling radius) and the no-karst volumes where no sample may lie.
//!
//! The potential is the product of three factors, each 1 when absent:
//! - the layer containing p (`[[geology.layers]]`, the first in scene order wins);
//! - a small construction tree (`[[geology.potential]]`, the last node is the root): primitives
//!   (sphere, box, stratum between two surfaces or elevations) worth `inside` within the shape,
//!   `outside` beyond `falloff` metres, and a smoothstep between; combined by `min`, `max` and
//!   `blend` (weighted mean) of earlier nodes;
//! - a background grid of per-node values read from a file (`[geology.grid]`, KarstNSim's box),
//!   trilinear inside, nearest node outside.
//!
//! A product keeps P in [0, 1] and lets each factor only lower the potential: marl stays
//! poorly karstifiable whatever the tree says.

use std::path::Path;

use serde::{Deserialize, Serialize};

use crate::file_error::FileError;
use crate::{Point, Surface};

/// A stratum's bound: an elevation or a named surface (horizon, fault or water table).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(untagged)]
pub enum Bound {
    Elevation(f64),
    Surface(String),
}

/// A volume: sphere, box, or the rock between two bounds.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(tag = "kind", rename_all = "snake_case", deny_unknown_fields)]
pub enum Shape {
    Sphere { centre: [f64; 3], radius: f64 },
    Box { min: [f64; 3], max: [f64; 3] },
    Stratum { top: Bound, bottom: Bound },
}

/// A layer of rock between two bounds (`[[geology.layers]]`).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Layer {
    pub name: String,
    /// Upper bound; absent: unbounded above.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub top: Option<Bound>,
    /// Lower bound; absent: unbounded below.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub bottom: Option<Bound>,
    /// Karstification potential of the rock, in [0, 1]; default 1.
    #[serde(default = "one")]
    pub potential: f64,
    /// Sampling radius in this layer (units of `[sampling]`); default `sampling.radius`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub radius: Option<f64>,
}

/// The kind of a potential node or of a no-karst volume.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum FieldKind {
    Sphere,
    Box,
    Stratum,
    Min,
    Max,
    Blend,
}

/// A no-karst volume (`[[geology.no_karst]]`, a sphere, box or stratum): no sample, hence no
/// conduit, lies inside.
pub type NoKarst = FieldNode;

/// A node of the potential tree (`[[geology.potential]]`), or a no-karst volume. Which fields
/// apply depends on `kind` (validated): sphere `centre` + `radius`; box `min` + `max`; stratum
/// `top` + `bottom`; min/max `of`; blend `of` + `weights`. Primitives also take `inside`,
/// `outside`, `falloff`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct FieldNode {
    pub name: String,
    pub kind: FieldKind,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub centre: Option<[f64; 3]>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub radius: Option<f64>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub min: Option<[f64; 3]>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub max: Option<[f64; 3]>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub top: Option<Bound>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub bottom: Option<Bound>,
    /// Value inside a primitive; default 1.
    #[serde(default = "one")]
    pub inside: f64,
    /// Value beyond `falloff` metres from a primitive; default 0.
    #[serde(default)]
    pub outside: f64,
    /// Width of the smooth transition outside a primitive, metres; default 0 (sharp).
    #[serde(default)]
    pub falloff: f64,
    /// Children (earlier nodes) of min, max, blend.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub of: Vec<String>,
    /// Blend weights, one per child, ≥ 0, not all 0.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub weights: Vec<f64>,
}

impl FieldNode {
    /// The volume of a primitive (None for combinations or missing fields).
    pub fn shape(&self) -> Option<Shape> {
        match self.kind {
            FieldKind::Sphere => Some(Shape::Sphere { centre: self.centre?, radius: self.radius? }),
            FieldKind::Box => Some(Shape::Box { min: self.min?, max: self.max? }),
            FieldKind::Stratum => {
                Some(Shape::Stratum { top: self.top.clone()?, bottom: self.bottom.clone()? })
            }
            FieldKind::Min | FieldKind::Max | FieldKind::Blend => None,
        }
    }

    /// The fields `kind` requires that are missing.
    pub fn missing(&self) -> Vec<&'static str> {
        let need: &[(&'static str, bool)] = match self.kind {
            FieldKind::Sphere => &[("centre", self.centre.is_some()), ("radius", self.radius.is_some())],
            FieldKind::Box => &[("min", self.min.is_some()), ("max", self.max.is_some())],
            FieldKind::Stratum => &[("top", self.top.is_some()), ("bottom", self.bottom.is_some())],
            FieldKind::Min | FieldKind::Max => &[("of", !self.of.is_empty())],
            FieldKind::Blend => &[("of", !self.of.is_empty()), ("weights", !self.weights.is_empty())],
        };
        need.iter().filter(|(_, present)| !present).map(|(f, _)| *f).collect()
    }

    fn falloff_at(&self, signed_distance: f64) -> f64 {
        if signed_distance <= 0.0 {
            return self.inside;
        }
        if signed_distance >= self.falloff {
            return self.outside;
        }
        let t = 1.0 - signed_distance / self.falloff;
        self.outside + (self.inside - self.outside) * t * t * (3.0 - 2.0 * t)
    }
}

/// `[geology.grid]`: per-node potentials from a file.
#[derive(Debug, Clone, PartialEq, Default, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct GridSpec {
    /// Text file, relative to the scene's folder (format in docs/scene.md).
    pub file: String,
    /// BLAKE3 of the file, filled when loaded.
    #[serde(default, skip_deserializing)]
    pub content: String,
    #[serde(skip)]
    pub values: std::sync::Arc<ValueGrid>,
}

/// A regular 3D grid of values at nodes origin + (i, j, k)·cell.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct ValueGrid {
    pub origin: [f64; 3],
    pub cell: [f64; 3],
    pub size: [usize; 3],
    pub values: Vec<f64>,
}

fn one() -> f64 {
    1.0
}

/// Looks up surfaces by name for strata.
pub trait Surfaces {
    fn surface(&self, name: &str) -> Option<&Surface>;
}

impl Bound {
    /// Elevation of the bound above (x, y).
    pub fn elevation(&self, x: f64, y: f64, surfaces: &impl Surfaces) -> f64 {
        match self {
            Bound::Elevation(z) => *z,
            Bound::Surface(name) => surfaces.surface(name).map_or(f64::NAN, |s| s.elevation_at(x, y)),
        }
    }
}

impl Shape {
    /// Signed distance (negative inside); vertical distance for strata.
    pub fn signed_distance(&self, p: Point, surfaces: &impl Surfaces) -> f64 {
        match self {
            Shape::Sphere { centre, radius } => p.distance(Point::from_array(*centre)) - radius,
            Shape::Box { min, max } => crate::Domain { min: *min, max: *max }.signed_distance(p),
            Shape::Stratum { top, bottom } => {
                (p.z - top.elevation(p.x, p.y, surfaces)).max(bottom.elevation(p.x, p.y, surfaces) - p.z)
            }
        }
    }
}

impl Layer {
    /// True when `p` lies between the layer's bounds.
    pub fn contains(&self, p: Point, surfaces: &impl Surfaces) -> bool {
        let below_top = self.top.as_ref().is_none_or(|t| p.z <= t.elevation(p.x, p.y, surfaces));
        let above_bottom = self.bottom.as_ref().is_none_or(|b| p.z >= b.elevation(p.x, p.y, surfaces));
        below_top && above_bottom
    }
}

/// Value of the potential tree at `p` (the last node is the root; nodes refer to earlier ones).
pub fn tree_value(nodes: &[FieldNode], p: Point, surfaces: &impl Surfaces) -> f64 {
    match nodes.last() {
        None => 1.0,
        Some(_) => node_value(nodes, nodes.len() - 1, p, surfaces),
    }
}

fn node_value(nodes: &[FieldNode], i: usize, p: Point, surfaces: &impl Surfaces) -> f64 {
    let node = &nodes[i];
    if let Some(shape) = node.shape() {
        return node.falloff_at(shape.signed_distance(p, surfaces));
    }
    let mut children = node.of.iter().map(|name| {
        nodes[..i]
            .iter()
            .position(|n| &n.name == name)
            .map_or(f64::NAN, |j| node_value(nodes, j, p, surfaces))
    });
    match node.kind {
        FieldKind::Min => children.fold(f64::INFINITY, f64::min),
        FieldKind::Max => children.fold(f64::NEG_INFINITY, f64::max),
        _ => {
            let total: f64 = node.weights.iter().sum();
            node.weights.iter().map(|w| w * children.next().unwrap_or(f64::NAN)).sum::<f64>() / total
        }
    }
}

impl ValueGrid {
    /// Reads the text format: `origin x y z`, `cell dx dy dz`, `size nx ny nz`, then
    /// nx·ny·nz values, x fastest, then y, then z; `#` starts a comment.
    pub fn read(path: &Path) -> Result<ValueGrid, FileError> {
        let file = path.display();
        let text = karst_artifact::files::read_regular_text(path, karst_artifact::files::MAX_DATA_BYTES)
            .map_err(|e| FileError::read(&file, e))?;
        let wrong = |problem: String| FileError::content(&file, problem);
        let mut words = text.lines().flat_map(|l| l.split('#').next().unwrap_or("").split_whitespace());
        let mut header = |key: &str| -> Result<[f64; 3], FileError> {
            match words.next() {
                Some(w) if w == key => {}
                other => return Err(wrong(format!("expected \"{key}\", found {other:?}"))),
            }
            let mut v = [0.0; 3];
            for x in &mut v {
                let w = words.next().ok_or_else(|| wrong(format!("{key} needs 3 numbers")))?;
                *x = w.parse().map_err(|_| wrong(format!("{key}: \"{w}\" is not a number")))?;
            }
            Ok(v)
        };
        let origin = header("origin")?;
        let cell = header("cell")?;
        let size = header("size")?;
        if origin.iter().chain(&cell).any(|v| !v.is_finite()) || cell.iter().any(|c| *c <= 0.0) {
            return Err(wrong(format!(
                "origin must be finite and cell sizes > 0, got {origin:?} and {cell:?}"
            )));
        }
        if size.iter().any(|n| *n < 1.0 || n.fract() != 0.0) {
            return Err(wrong(format!("size must be three integers ≥ 1, got {size:?}")));
        }
        let size = size.map(|n| n as usize);
        let values: Vec<f64> = words
            .enumerate()
            .map(|(i, w)| match w.parse::<f64>() {
                Ok(v) if (0.0..=1.0).contains(&v) => Ok(v),
                _ => Err(wrong(format!("value {i} = \"{w}\" is not a number in [0, 1]"))),
            })
            .collect::<Result<_, _>>()?;
        let expected = size.iter().try_fold(1usize, |n, &s| n.checked_mul(s));
        if expected != Some(values.len()) {
            return Err(wrong(format!("size {size:?} does not match the {} values found", values.len())));
        }
        Ok(ValueGrid { origin, cell, size, values })
    }

    /// Trilinear value at `p`, clamped to the grid.
    pub fn at(&self, p: Point) -> f64 {
        let mut base = [0usize; 3];
        let mut frac = [0.0; 3];
        for a in 0..3 {
            let t = ((p[a] - self.origin[a]) / self.cell[a]).clamp(0.0, (self.size[a] - 1) as f64);
            base[a] = (t.floor() as usize).min(self.size[a].saturating_sub(2));
            frac[a] = if self.size[a] > 1 { t - base[a] as f64 } else { 0.0 };
        }
        let mut sum = 0.0;
        for corner in 0..8 {
            let mut w = 1.0;
            let mut idx = [0usize; 3];
            for a in 0..3 {
                let up = (corner >> a) & 1 == 1;
                w *= if up { frac[a] } else { 1.0 - frac[a] };
                idx[a] = (base[a] + usize::from(up)).min(self.size[a] - 1);
            }
            if w > 0.0 {
                sum += w * self.values[(idx[2] * self.size[1] + idx[1]) * self.size[0] + idx[0]];
            }
        }
        sum
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    struct NoSurfaces;
    impl Surfaces for NoSurfaces {
        fn surface(&self, _: &str) -> Option<&Surface> {
            None
        }
    }

    fn node(name: &str, kind: FieldKind) -> FieldNode {
        FieldNode {
            name: name.into(),
            kind,
            centre: None,
            radius: None,
            min: None,
            max: None,
            top: None,
            bottom: None,
            inside: 1.0,
            outside: 0.0,
            falloff: 0.0,
            of: vec![],
            weights: vec![],
        }
    }

    #[test]
    fn primitives_fall_off_and_combine() {
        let lens = FieldNode {
            centre: Some([0.0; 3]),
            radius: Some(10.0),
            outside: 0.2,
            falloff: 10.0,
            ..node("lens", FieldKind::Sphere)
        };
        let bed = FieldNode {
            top: Some(Bound::Elevation(5.0)),
            bottom: Some(Bound::Elevation(-5.0)),
            inside: 0.6,
            ..node("bed", FieldKind::Stratum)
        };
        let mix = FieldNode {
            of: vec!["lens".into(), "bed".into()],
            weights: vec![3.0, 1.0],
            ..node("mix", FieldKind::Blend)
        };
        let top = FieldNode { of: vec!["mix".into(), "bed".into()], ..node("top", FieldKind::Max) };
        assert!(mix.missing().is_empty() && node("x", FieldKind::Box).missing() == ["min", "max"]);
        let nodes = vec![lens, bed, mix, top];
        let at = |x: f64, z: f64| tree_value(&nodes, Point::new(x, 0.0, z), &NoSurfaces);
        assert_eq!(at(0.0, 0.0), (3.0 * 1.0 + 0.6) / 4.0);
        assert_eq!(at(40.0, 0.0), 0.6, "max with the bed far from the lens");
        assert_eq!(at(40.0, 20.0), (3.0 * 0.2) / 4.0);
        let halfway = at(15.0, 20.0);
        assert!(halfway > 0.15 && halfway < 0.75, "{halfway}");
        assert_eq!(tree_value(&[], Point::ZERO, &NoSurfaces), 1.0);
    }

    #[test]
    fn value_grid_is_trilinear_and_clamped() {
        let g = ValueGrid {
            origin: [0.0; 3],
            cell: [10.0; 3],
            size: [2, 2, 1],
            values: vec![0.0, 1.0, 0.0, 1.0],
        };
        assert!((g.at(Point::new(2.5, 7.0, 3.0)) - 0.25).abs() < 1e-12);
        assert_eq!(g.at(Point::new(50.0, -5.0, 0.0)), 1.0);
    }
}
