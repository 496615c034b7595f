//! `[streams]`: the surface waterfall network fed by the springs (Emilien et al. 2015 §4–6,
//! docs/streams.md), and the user's controller curves (`[[streams.curves]]`).

use serde::{Deserialize, Serialize};

use crate::Scene;
use crate::validate::Checks;

#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct StreamsParams {
    /// Horizontal step of the trajectories over the terrain, metres.
    pub step: f64,
    /// Smallest slope of running water (Fig. 5's s_min), dimensionless (rise over run): each
    /// point of a trajectory or a controller curve lies at least this much lower per metre.
    pub min_slope: f64,
    /// Cell edge of the grid of the surface catchment and of the pools' flood fill, metres.
    pub catchment_cell: f64,
    /// Effective runoff of the terrain draining to the streams, mm per year.
    pub runoff: f64,
    /// Discharges, m³/s, mapped to the paper's flow units 1 and 8 (log scale).
    pub flow_range: [f64; 2],
    /// Speed of running water per radian of slope, m/s (§5.2.2, k = 10).
    pub speed_factor: f64,
    /// Depth of running water ζ = depth_factor · Q^0.4 (Q in m³/s), metres.
    pub depth_factor: f64,
    /// Speed at which a spring's water leaves its mouth, m/s.
    pub mouth_speed: f64,
    /// Radius of the passage joining a spring's conduit to its mouth on the terrain, metres.
    pub mouth_radius: f64,
    /// Slope of the riverbeds' and pools' sides above the water (rise over run).
    pub bank_slope: f64,
    /// Thinnest falling sheet of water, metres (thinner sheets are drawn this thick).
    pub sheet_thickness: f64,
    /// A pool larger than this is a lake, m² (reported).
    pub lake_area: f64,
    /// Longest trajectory from one source, metres.
    pub max_length: f64,
    /// A controller curve's end within this distance of a spring, another curve or a pool
    /// joins it, metres.
    pub snap: f64,
    /// The user's controller curves (§4.1).
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub curves: Vec<Curve>,
}

/// The three controllers of §4.1.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum CurveKind {
    /// Water in contact with the ground, along a Cardinal spline through the points.
    Contact,
    /// Water in the air: a parabola from the first point (the lip) to the second.
    FreeFall,
    /// A flat pool: the closed Cardinal spline through the points, at their mean elevation.
    Pool,
}

/// `[[streams.curves]]`: one controller curve.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Curve {
    pub name: String,
    pub kind: CurveKind,
    /// Control points `[x, y, z]`, upstream first.
    pub points: Vec<[f64; 3]>,
    /// Discharge entering at the first point when it joins no spring, curve or pool, m³/s.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub flow: Option<f64>,
    /// Tension of the Cardinal spline in [0, 1] (0: Catmull–Rom, 1: straight lines).
    #[serde(default)]
    pub tension: f64,
}

impl Default for StreamsParams {
    fn default() -> Self {
        StreamsParams {
            step: 2.0,
            min_slope: 0.01,
            catchment_cell: 5.0,
            runoff: 300.0,
            flow_range: [0.005, 500.0],
            speed_factor: 10.0,
            depth_factor: 0.3,
            mouth_speed: 1.0,
            mouth_radius: 1.0,
            bank_slope: 1.0,
            sheet_thickness: 0.5,
            lake_area: 5000.0,
            max_length: 5000.0,
            snap: 3.0,
            curves: Vec::new(),
        }
    }
}

impl StreamsParams {
    pub(crate) fn check(&self, scene: &Scene, c: &mut Checks) {
        for (field, value) in [
            ("streams.step", self.step),
            ("streams.min_slope", self.min_slope),
            ("streams.catchment_cell", self.catchment_cell),
            ("streams.speed_factor", self.speed_factor),
            ("streams.depth_factor", self.depth_factor),
            ("streams.mouth_speed", self.mouth_speed),
            ("streams.mouth_radius", self.mouth_radius),
            ("streams.bank_slope", self.bank_slope),
            ("streams.sheet_thickness", self.sheet_thickness),
            ("streams.lake_area", self.lake_area),
            ("streams.max_length", self.max_length),
            ("streams.snap", self.snap),
        ] {
            c.positive(field, value);
        }
        c.non_negative("streams.runoff", self.runoff);
        let [lo, hi] = self.flow_range;
        c.positive("streams.flow_range", lo);
        c.positive("streams.flow_range", hi);
        if lo.is_finite() && hi.is_finite() && hi <= lo {
            c.report("streams.flow_range", format!("[{lo}, {hi}] is not a range (max ≤ min)"));
        }
        for (i, curve) in self.curves.iter().enumerate() {
            curve.check(i, scene, c);
            if self.curves[..i].iter().any(|o| o.name == curve.name) {
                c.report(&format!("streams.curves[{i}].name"), format!("\"{}\" is used twice", curve.name));
            }
        }
    }
}

impl Curve {
    fn check(&self, i: usize, scene: &Scene, c: &mut Checks) {
        let at = |f: &str| format!("streams.curves[{i}].{f}");
        let name = &self.name;
        let fewest = match self.kind {
            CurveKind::Contact => 2,
            CurveKind::FreeFall => 2,
            CurveKind::Pool => 3,
        };
        if self.points.len() < fewest {
            let what = match self.points.len() {
                0 => "no point".to_string(),
                1 => "a single point".to_string(),
                n => format!("{n} points"),
            };
            c.report(
                &at("points"),
                format!("curve \"{name}\" has {what}: a {:?} curve needs at least {fewest}", self.kind),
            );
        }
        if self.kind == CurveKind::FreeFall && self.points.len() > 2 {
            c.report(
                &at("points"),
                format!(
                    "free fall \"{name}\" has {} points: give its lip and its foot only",
                    self.points.len()
                ),
            );
        }
        for (j, p) in self.points.iter().enumerate() {
            let field = format!("streams.curves[{i}].points[{j}]");
            if !c.finite(&field, p) {
                continue;
            }
            if !scene.domain.contains(karst_geology::Point::from_array(*p)) {
                c.report(
                    &field,
                    format!("curve \"{name}\": [{}, {}, {}] is outside the domain", p[0], p[1], p[2]),
                );
            }
        }
        if let Some(flow) = self.flow {
            c.non_negative(&at("flow"), flow);
        }
        if !(0.0..=1.0).contains(&self.tension) {
            c.report(&at("tension"), format!("must be in [0, 1], got {}", self.tension));
        }
    }
}

#[cfg(test)]
mod tests {
    use crate::params::test_scene;

    fn problems(streams: &str) -> Vec<String> {
        test_scene::problems(streams)
    }

    #[test]
    fn good_curves_pass() {
        let good = "[[streams.curves]]\nname = \"c\"\nkind = \"contact\"\npoints = [[10, 10, 40], [20, 10, 39]]\nflow = 0.1\n\
                    [[streams.curves]]\nname = \"f\"\nkind = \"free_fall\"\npoints = [[20, 10, 39], [22, 10, 20]]";
        assert!(problems(good).is_empty(), "{:?}", problems(good));
    }

    #[test]
    fn bad_curves_name_the_entry() {
        let p = problems("[[streams.curves]]\nname = \"empty\"\nkind = \"contact\"\npoints = []");
        assert!(p[0].contains("streams.curves[0].points: curve \"empty\" has no point"), "{p:?}");
        let p = problems("[[streams.curves]]\nname = \"one\"\nkind = \"contact\"\npoints = [[1, 2, 3]]");
        assert!(p[0].contains("curve \"one\" has a single point"), "{p:?}");
        let p = problems(
            "[[streams.curves]]\nname = \"n\"\nkind = \"contact\"\npoints = [[1, 2, 3], [4, nan, 2]]",
        );
        assert!(p[0].contains("streams.curves[0].points[1]: NaN is not a finite number"), "{p:?}");
        let p = problems(
            "[[streams.curves]]\nname = \"o\"\nkind = \"contact\"\npoints = [[1, 2, 3], [400, 2, 2]]",
        );
        assert!(p[0].contains("curve \"o\": [400, 2, 2] is outside the domain"), "{p:?}");
        assert!(p[0].starts_with(":24:"), "the line of the curve: {p:?}");
        let p = problems(
            "[[streams.curves]]\nname = \"f\"\nkind = \"free_fall\"\npoints = [[1, 2, 3], [2, 2, 2], [3, 2, 1]]",
        );
        assert!(p[0].contains("give its lip and its foot only"), "{p:?}");
        let p = problems("[streams]\nflow_range = [5, 1]\nstep = 0");
        assert_eq!(p.len(), 2, "{p:?}");
        assert!(
            problems("[[streams.curves]]\nname = \"x\"\nkind = \"river\"\npoints = []")[0]
                .contains("unknown variant `river`")
        );
    }
}
