//! The verdict of a run in plain words (issue 38): how many of karstnet's ten metrics lie in
//! the real-cave ranges and, for each outside, what it means for the network's shape, the
//! parameter that moves it and that parameter's value in this run (the scene's, or the default
//! the skeleton derived from the scene, `skeleton.json`'s `derived`).
//!
//! Each hint names the mechanism of docs/skeleton.md that moves the metric ("Networks that pass
//! for real caves"): tributaries for the branch lengths and the degrees, meanders for the
//! tortuosity and the azimuths, cohesion for the trunks.

use std::collections::BTreeMap;

use karst_scene::params::{SamplingParams, SkeletonParams};

use crate::ranges::Compared;

/// The run's parameters a hint may cite: the scene's `[skeleton]` and `[sampling]`, and the
/// values the skeleton derived for what they left out.
pub struct Parameters<'a> {
    pub skeleton: &'a SkeletonParams,
    pub sampling: &'a SamplingParams,
    pub derived: &'a BTreeMap<String, serde_json::Value>,
}

impl Parameters<'_> {
    /// `field`'s value in this run, as the scene would write it.
    fn value(&self, field: &str) -> String {
        if let Some(v) = self.derived.get(field) {
            return format!("{v} (derived from the scene)");
        }
        match field {
            "sampling.radius" => self.sampling.radius.map_or("derived".into(), |r| r.to_string()),
            _ => self.number(field).map_or("?".into(), |v| v.to_string()),
        }
    }

    /// `field`'s value in this run as a number, when it has one.
    fn number(&self, field: &str) -> Option<f64> {
        if let Some(v) = self.derived.get(field) {
            return v.as_f64();
        }
        let s = self.skeleton;
        Some(match field {
            "skeleton.amplification_points" => s.amplification_points.unwrap_or(0) as f64,
            "skeleton.amplification_steps" => s.amplification_steps as f64,
            "skeleton.amplification_exponent" => s.amplification_exponent,
            "skeleton.confluence_attraction" => s.confluence_attraction,
            "skeleton.dead_end_fraction" => s.dead_end_fraction,
            "skeleton.sinuosity" => s.sinuosity,
            "skeleton.cohesion_phreatic" => s.cohesion_phreatic,
            _ => return None,
        })
    }

    /// Whether `field` already sits at the end of its valid range that the advice would move it
    /// past (a fraction at 1 cannot be raised, a count at 0 cannot be lowered).
    fn at_limit(&self, field: &str, raise: bool) -> bool {
        let Some(v) = self.number(field) else { return false };
        let (lo, hi) = match field {
            "skeleton.confluence_attraction"
            | "skeleton.dead_end_fraction"
            | "skeleton.cohesion_phreatic" => (0.0, 1.0),
            "skeleton.sinuosity" => (1.0, 3.0),
            _ => (0.0, f64::INFINITY),
        };
        if raise { v >= hi } else { v <= lo }
    }
}

/// `"8/10 inside real-cave ranges"`.
pub fn verdict(karstnet: &BTreeMap<String, Compared>) -> String {
    let inside = karstnet.values().filter(|c| c.inside).count();
    format!("{inside}/{} inside real-cave ranges", karstnet.len())
}

/// One hint per metric outside its range, in the ranges' order.
pub fn hints(karstnet: &BTreeMap<String, Compared>, parameters: &Parameters) -> Vec<String> {
    karstnet.iter().filter(|(_, c)| !c.inside).map(|(key, c)| hint(key, c, parameters)).collect()
}

fn hint(key: &str, c: &Compared, p: &Parameters) -> String {
    let r = &c.real_caves;
    let high = c.value > r.max;
    let (bound, sign) = if high { (r.max, ">") } else { (r.min, "<") };
    if !c.value.is_finite() {
        return format!("{key} undefined: the network has too few branches for it; add sinks or tributaries");
    }
    let (words, field, raise) = advice(key, high);
    let action = if p.at_limit(field, raise) {
        "as far as it goes: the sinks, the springs and the cost graph shape this, not the tributaries"
    } else if raise {
        "raise it"
    } else {
        "lower it"
    };
    format!(
        "{key} {} {sign} {}: {words} — {field} is {}, {action}",
        short(c.value),
        short(bound),
        p.value(field)
    )
}

/// What a metric outside on that side says about the network, the parameter that moves it, and
/// whether to raise it.
fn advice(key: &str, high: bool) -> (&'static str, &'static str, bool) {
    match (key, high) {
        ("mean length", true) => ("branches too long and too few", "skeleton.amplification_points", true),
        ("mean length", false) => ("branches too short", "skeleton.amplification_points", false),
        ("cv length", false) => {
            ("branch lengths too even (few long, few short)", "skeleton.amplification_exponent", false)
        }
        ("cv length", true) => {
            ("a few branches much longer than all others", "skeleton.amplification_exponent", true)
        }
        ("length entropy", true) => {
            ("branch lengths spread too evenly", "skeleton.confluence_attraction", true)
        }
        ("length entropy", false) => {
            ("nearly every branch of one length", "skeleton.confluence_attraction", false)
        }
        ("tortuosity", false) => ("passages too straight", "skeleton.sinuosity", true),
        ("tortuosity", true) => ("passages wind too much", "skeleton.sinuosity", false),
        ("orientation entropy", true) => ("azimuths spread too evenly", "skeleton.sinuosity", false),
        ("orientation entropy", false) => ("passages all run one way", "skeleton.sinuosity", true),
        ("aspl", false) => ("too few junctions between the ends", "skeleton.amplification_steps", true),
        ("aspl", true) => ("junctions strung along too long paths", "skeleton.amplification_steps", false),
        ("cpd", true) => ("the network hangs on one junction", "skeleton.amplification_points", true),
        ("cpd", false) => ("no trunk dominates", "skeleton.cohesion_phreatic", false),
        ("mean degree", false) => ("too many dead ends", "skeleton.dead_end_fraction", false),
        ("mean degree", true) => ("too many loops", "skeleton.dead_end_fraction", true),
        ("cv degree", true) => ("degrees too unequal (a few hubs)", "skeleton.amplification_points", true),
        ("cv degree", false) => ("degrees too alike", "skeleton.dead_end_fraction", true),
        ("correlation vertex degree", true) => (
            "junctions join junctions (real side passages hang off passages)",
            "skeleton.amplification_points",
            true,
        ),
        (_, _) => ("dead ends hang off hubs", "skeleton.amplification_points", false),
    }
}

fn short(v: f64) -> String {
    if v.abs() >= 100.0 { format!("{v:.0} m") } else { format!("{v:.3}") }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::ranges::real_cave_ranges;

    fn compared(key: &str, value: f64) -> BTreeMap<String, Compared> {
        let mut all: BTreeMap<String, Compared> = BTreeMap::new();
        for (k, range) in real_cave_ranges() {
            let mid = if k == key { value } else { 0.5 * (range.min + range.max) };
            let inside = range.contains(mid);
            all.insert(k, Compared { value: mid, real_caves: range, inside });
        }
        all
    }

    #[test]
    fn long_branches_cite_the_derived_tributary_count() {
        let skeleton = SkeletonParams::default();
        let sampling = SamplingParams::default();
        let derived = BTreeMap::from([("skeleton.amplification_points".to_string(), serde_json::json!(12))]);
        let p = Parameters { skeleton: &skeleton, sampling: &sampling, derived: &derived };
        let karstnet = compared("mean length", 2832.0);
        assert_eq!(verdict(&karstnet), "9/10 inside real-cave ranges");
        let hints = hints(&karstnet, &p);
        assert_eq!(hints.len(), 1);
        assert!(hints[0].starts_with("mean length 2832 m > 332 m: branches too long"), "{}", hints[0]);
        assert!(
            hints[0].contains("skeleton.amplification_points is 12 (derived from the scene), raise it"),
            "{}",
            hints[0]
        );
    }

    #[test]
    fn straight_passages_cite_the_scene_sinuosity() {
        let skeleton = SkeletonParams { sinuosity: 1.05, ..SkeletonParams::default() };
        let sampling = SamplingParams::default();
        let derived = BTreeMap::new();
        let p = Parameters { skeleton: &skeleton, sampling: &sampling, derived: &derived };
        let karstnet = compared("tortuosity", 1.03);
        let hints = hints(&karstnet, &p);
        assert_eq!(
            hints,
            ["tortuosity 1.030 < 1.121: passages too straight — skeleton.sinuosity is 1.05, raise it"]
        );
    }

    #[test]
    fn a_parameter_at_its_limit_is_not_pushed_past_it() {
        let skeleton = SkeletonParams { amplification_points: None, ..SkeletonParams::default() };
        let sampling = SamplingParams::default();
        let derived = BTreeMap::new();
        let p = Parameters { skeleton: &skeleton, sampling: &sampling, derived: &derived };
        let karstnet = compared("correlation vertex degree", -0.7);
        let hints = hints(&karstnet, &p);
        assert_eq!(hints.len(), 1);
        assert!(hints[0].contains("skeleton.amplification_points is 0, as far as it goes"), "{}", hints[0]);
    }

    #[test]
    fn every_range_inside_gives_no_hint() {
        let skeleton = SkeletonParams::default();
        let sampling = SamplingParams::default();
        let derived = BTreeMap::new();
        let p = Parameters { skeleton: &skeleton, sampling: &sampling, derived: &derived };
        let karstnet = compared("tortuosity", 1.3);
        assert_eq!(verdict(&karstnet), "10/10 inside real-cave ranges");
        assert!(hints(&karstnet, &p).is_empty());
    }
}
