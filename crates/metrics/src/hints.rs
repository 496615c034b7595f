//! The verdict of a run in plain words (issue 38): how many of karstnet's ten metrics lie in
//! the real-cave ranges and, for each outside, what it means for the network's shape, the
//! parameter that moves it and that parameter's value in this run (the scene's, or the default
//! the skeleton derived from the scene, `skeleton.json`'s `derived`).
//!
//! When the scene's `[calibrate]` names a target (`like` or `target`), the verdict and the hints
//! are relative to it instead: how many metrics lie within [`ON_TARGET`] of a real-cave range of
//! the target's value, the distance the calibration minimises, and for each metric off target
//! how far (in real-cave ranges) and which way, with the same parameter and advice.
//!
//! Each hint names the mechanism of docs/skeleton.md that moves the metric ("Networks that pass
//! for real caves"): tributaries for the branch lengths and the degrees, meanders for the
//! tortuosity and the azimuths, cohesion for the trunks.

use std::collections::BTreeMap;

use karst_scene::params::{SamplingParams, SkeletonParams};

use serde::{Deserialize, Serialize};

use crate::aim::{self, ON_TARGET, Target};
use crate::ranges::{CHARACTERIZE_KEYS, Compared};

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
            _ => self.number(field).map_or("?".into(), plain),
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

/// The verdict of a report: against its target when it has one (with the real-cave count
/// after it), else against the real-cave ranges.
pub fn verdict_of(report: &crate::MetricsReport) -> String {
    match &report.target {
        Some(target) => format!("{}; {}", target_line(target), verdict(&report.karstnet)),
        None => verdict(&report.karstnet),
    }
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
        return undefined(key);
    }
    format!("{key} {} {sign} {}: {}", short(c.value), short(bound), remedy(key, high, p))
}

fn undefined(key: &str) -> String {
    format!("{key} undefined: the network has too few branches for it; add sinks or tributaries")
}

/// What the metric says, the parameter that moves it, its value and which way to move it.
fn remedy(key: &str, high: bool, p: &Parameters) -> String {
    let (words, field, raise) = advice(key, high);
    let action = if p.at_limit(field, raise) {
        "as far as it goes: the sinks, the springs and the cost graph shape this, not the tributaries"
    } else if raise {
        "raise it"
    } else {
        "lower it"
    };
    format!("{words} — {field} is {}, {action}", p.value(field))
}

/// A run against its calibration target (`metrics.json`'s `target`).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct TargetVerdict {
    /// The target's name (the published network, or the cave's file as the scene names it).
    pub name: String,
    /// The calibration's distance of this network to the target.
    pub distance: f64,
    /// Metrics within [`ON_TARGET`] of a real-cave range of the target's value.
    pub on_target: usize,
    /// Metrics the target defines (the others are left out).
    pub defined: usize,
    /// The target's value of each metric (null: undefined).
    pub values: BTreeMap<String, Option<f64>>,
}

/// The run's metrics against `target`.
pub fn against(karstnet: &BTreeMap<String, Compared>, target: &Target) -> TargetVerdict {
    let statistics: [f64; CHARACTERIZE_KEYS.len()] =
        CHARACTERIZE_KEYS.map(|key| karstnet.get(key).map_or(f64::NAN, |c| c.value));
    let widths = aim::widths();
    let offsets: Vec<f64> = (0..statistics.len())
        .filter_map(|i| aim::normalised(statistics[i], target.statistics[i], widths[i]))
        .collect();
    TargetVerdict {
        name: target.name.clone(),
        distance: aim::distance(&statistics, &target.statistics, &widths),
        on_target: offsets.iter().filter(|d| d.abs() <= ON_TARGET).count(),
        defined: offsets.len(),
        values: CHARACTERIZE_KEYS
            .iter()
            .zip(target.statistics)
            .map(|(k, v)| (k.to_string(), v.is_finite().then_some(v)))
            .collect(),
    }
}

/// `"6/10 on target (Sakany), distance 0.171"`.
pub fn target_line(verdict: &TargetVerdict) -> String {
    format!(
        "{}/{} on target ({}), distance {:.3}",
        verdict.on_target, verdict.defined, verdict.name, verdict.distance
    )
}

/// One hint per metric farther than [`ON_TARGET`] of a real-cave range from the target's value,
/// in the ranges' order: how far and which way, and the parameter that moves it.
pub fn target_hints(
    karstnet: &BTreeMap<String, Compared>,
    verdict: &TargetVerdict,
    parameters: &Parameters,
) -> Vec<String> {
    let widths = aim::widths();
    karstnet
        .iter()
        .filter_map(|(key, c)| {
            let i = CHARACTERIZE_KEYS.iter().position(|k| k == key)?;
            let goal = (*verdict.values.get(key.as_str())?)?;
            let offset = aim::normalised(c.value, goal, widths[i])?;
            if offset.abs() <= ON_TARGET {
                return None;
            }
            if !c.value.is_finite() {
                return Some(undefined(key));
            }
            let high = c.value > goal;
            let sign = if high { ">" } else { "<" };
            Some(format!(
                "{key} {} {sign} {} of {} ({offset:+.2} ranges): {}",
                short(c.value),
                short(goal),
                verdict.name,
                remedy(key, high, parameters)
            ))
        })
        .collect()
}

/// What a metric outside on that side says about the network, the parameter that moves it, and
/// whether to raise it.
fn advice(key: &str, high: bool) -> (&'static str, &'static str, bool) {
    match (key, high) {
        ("mean length", true) => ("branches too long and too few", "skeleton.amplification_points", true),
        ("mean length", false) => ("branches too short", "skeleton.amplification_points", false),
        ("cv length", false) => (
            "branch lengths too even: side passages cut every stretch to one length",
            "skeleton.amplification_points",
            false,
        ),
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
        ("cpd", true) => {
            ("the network hangs on one junction: no loop bypasses it", "skeleton.dead_end_fraction", false)
        }
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

/// A parameter's value with at most four decimals, trailing zeros dropped (`0.8818`, `1.05`,
/// `12`): a calibrated value carries all of a float's digits.
fn plain(v: f64) -> String {
    let text = format!("{v:.4}");
    let text = text.trim_end_matches('0').trim_end_matches('.');
    if text == "-0" { "0".into() } else { text.to_string() }
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
    fn a_dominant_junction_asks_for_loops() {
        let skeleton = SkeletonParams::default();
        let sampling = SamplingParams::default();
        let derived = BTreeMap::new();
        let p = Parameters { skeleton: &skeleton, sampling: &sampling, derived: &derived };
        let hints = hints(&compared("cpd", 0.62), &p);
        assert_eq!(hints.len(), 1);
        assert!(hints[0].starts_with("cpd 0.620 > 0.572: the network hangs on one junction"), "{}", hints[0]);
        assert!(hints[0].contains("skeleton.dead_end_fraction is 0.85, lower it"), "{}", hints[0]);
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

    /// A target whose every metric is the middle of its real-cave range, but `key` at `value`.
    fn target_with(key: &str, value: f64) -> Target {
        let ranges = real_cave_ranges();
        let statistics =
            CHARACTERIZE_KEYS.map(|k| if k == key { value } else { 0.5 * (ranges[k].min + ranges[k].max) });
        Target { name: "Somecave".into(), statistics }
    }

    #[test]
    fn against_a_target_the_hint_says_how_far_which_way_and_what_moves_it() {
        let skeleton = SkeletonParams::default();
        let sampling = SamplingParams::default();
        let derived = BTreeMap::from([("skeleton.amplification_points".to_string(), serde_json::json!(12))]);
        let p = Parameters { skeleton: &skeleton, sampling: &sampling, derived: &derived };
        // Inside the real-cave range, but well above the target's: a hint all the same.
        let karstnet = compared("mean length", 300.0);
        let range = &karstnet["mean length"].real_caves;
        assert!(karstnet["mean length"].inside);
        let target = target_with("mean length", 60.0);
        let verdict = against(&karstnet, &target);
        assert_eq!((verdict.on_target, verdict.defined), (9, 10));
        let offset = (300.0 - 60.0) / (range.max - range.min);
        assert!((verdict.distance - (offset * offset / 10.0).sqrt()).abs() < 1e-12);
        let hints = target_hints(&karstnet, &verdict, &p);
        assert_eq!(hints.len(), 1, "{hints:?}");
        assert_eq!(
            hints[0],
            format!(
                "mean length 300 m > 60.000 of Somecave ({offset:+.2} ranges): branches too long and too \
                 few — skeleton.amplification_points is 12 (derived from the scene), raise it"
            )
        );
        assert!(target_line(&verdict).starts_with("9/10 on target (Somecave), distance "));
    }

    #[test]
    fn below_the_target_the_advice_turns_round() {
        let skeleton = SkeletonParams { sinuosity: 1.4, ..SkeletonParams::default() };
        let sampling = SamplingParams::default();
        let derived = BTreeMap::new();
        let p = Parameters { skeleton: &skeleton, sampling: &sampling, derived: &derived };
        let karstnet = compared("tortuosity", 1.2);
        let above = against(&karstnet, &target_with("tortuosity", 1.0));
        let high = target_hints(&karstnet, &above, &p);
        assert_eq!(high.len(), 1, "{high:?}");
        assert!(high[0].starts_with("tortuosity 1.200 > 1.000 of Somecave (+"), "{}", high[0]);
        assert!(
            high[0].ends_with("passages wind too much — skeleton.sinuosity is 1.4, lower it"),
            "{}",
            high[0]
        );
        let below = against(&karstnet, &target_with("tortuosity", 1.5));
        let low = target_hints(&karstnet, &below, &p);
        assert!(low[0].starts_with("tortuosity 1.200 < 1.500 of Somecave (-"), "{}", low[0]);
        assert!(
            low[0].ends_with("passages too straight — skeleton.sinuosity is 1.4, raise it"),
            "{}",
            low[0]
        );
    }

    #[test]
    fn on_target_outside_the_ranges_gives_no_hint_and_undefined_targets_are_left_out() {
        let skeleton = SkeletonParams::default();
        let sampling = SamplingParams::default();
        let derived = BTreeMap::new();
        let p = Parameters { skeleton: &skeleton, sampling: &sampling, derived: &derived };
        let karstnet = compared("mean length", 2832.0);
        assert!(!karstnet["mean length"].inside);
        let mut target = target_with("mean length", 2832.0);
        target.statistics[0] = f64::NAN;
        let verdict = against(&karstnet, &target);
        assert_eq!((verdict.on_target, verdict.defined), (9, 9));
        assert!(target_hints(&karstnet, &verdict, &p).is_empty());
        assert_eq!(verdict.values[CHARACTERIZE_KEYS[0]], None);
    }
}
