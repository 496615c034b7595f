//! How a network compares with real caves: the minimum and maximum of each metric of karstnet's
//! `characterize_graph()` over the cave networks of Collon et al. 2017 (Geomorphology 283, with
//! the 2021 corrigendum), as computed by karstnet 1.2.5 (`data/real-cave-ranges.json`, embedded
//! at build time).
//!
//! A value is inside when `min ≤ value ≤ max` up to a relative [`RANGE_SLACK`] of the bound: the
//! bounds are themselves floating-point results of karstnet, and the same ratio (−5/9, say)
//! computed in another order may differ in the last bit. An undefined value (NaN, e.g. the
//! tortuosity of a network made only of loops) is outside.

use std::collections::BTreeMap;

use serde::{Deserialize, Serialize};

use crate::Metrics;

/// Relative rounding allowance on a range bound: a few units in the last place of an f64, far
/// below any difference between caves.
pub const RANGE_SLACK: f64 = 1e-12;

/// The keys of `characterize_graph()`, in karstnet's order.
pub const CHARACTERIZE_KEYS: [&str; 10] = [
    "mean length",
    "cv length",
    "length entropy",
    "tortuosity",
    "orientation entropy",
    "aspl",
    "cpd",
    "mean degree",
    "cv degree",
    "correlation vertex degree",
];

const RANGES_JSON: &str = include_str!("../data/real-cave-ranges.json");

/// The range of one metric over the real caves.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct CaveRange {
    pub min: f64,
    pub max: f64,
    /// The cave with the smallest value.
    pub min_network: String,
    /// The cave with the largest value.
    pub max_network: String,
    /// Number of caves.
    pub n: usize,
}

impl CaveRange {
    /// Whether `value` lies in `[min, max]`, each bound widened by [`RANGE_SLACK`] of its
    /// magnitude (NaN never does).
    pub fn contains(&self, value: f64) -> bool {
        let slack = |bound: f64| RANGE_SLACK * bound.abs();
        (self.min - slack(self.min)..=self.max + slack(self.max)).contains(&value)
    }
}

/// One metric of a network beside its real-cave range.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Compared {
    #[serde(with = "crate::nullable")]
    pub value: f64,
    pub real_caves: CaveRange,
    /// Whether the value falls inside the real-cave range.
    pub inside: bool,
}

#[derive(Deserialize)]
struct RangesFile {
    ranges: BTreeMap<String, CaveRange>,
}

/// The real-cave range of every `characterize_graph()` key.
pub fn real_cave_ranges() -> BTreeMap<String, CaveRange> {
    let file: RangesFile = serde_json::from_str(RANGES_JSON).expect("the embedded ranges are valid JSON");
    file.ranges
}

/// Every `characterize_graph()` metric of `metrics` beside its range, in karstnet's order.
pub fn compare(metrics: &Metrics) -> Vec<(&'static str, Compared)> {
    let ranges = real_cave_ranges();
    let values: BTreeMap<&str, f64> = metrics.to_pairs().into_iter().collect();
    CHARACTERIZE_KEYS
        .iter()
        .map(|&key| {
            let range = ranges[key].clone();
            let value = values[key];
            (key, Compared { value, inside: range.contains(value), real_caves: range })
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::{Network, characterize};

    #[test]
    fn every_characterize_key_has_a_range() {
        let ranges = real_cave_ranges();
        assert_eq!(ranges.len(), CHARACTERIZE_KEYS.len());
        for key in CHARACTERIZE_KEYS {
            let r = &ranges[key];
            assert!(r.min < r.max && r.n > 30, "{key}");
        }
    }

    #[test]
    fn inside_follows_the_range_and_nan_is_outside() {
        let r = CaveRange { min: 1.0, max: 2.0, min_network: "a".into(), max_network: "b".into(), n: 2 };
        assert!(r.contains(1.0) && r.contains(2.0) && r.contains(1.5));
        assert!(!r.contains(0.99) && !r.contains(2.01) && !r.contains(f64::NAN));
    }

    #[test]
    fn a_bound_computed_in_another_order_still_counts_as_inside() {
        let min = -0.5555555555555555;
        let r = CaveRange { min, max: -0.15, min_network: "a".into(), max_network: "b".into(), n: 2 };
        let same_ratio = -5.0 / 9.0 - f64::EPSILON / 2.0;
        assert!(same_ratio < min && r.contains(same_ratio));
        assert!(!r.contains(-0.5555556));
    }

    #[test]
    fn a_straight_conduit_is_too_simple_for_a_cave() {
        let net = Network { nodes: vec![[0.0; 3], [30.0, 40.0, 0.0]], links: vec![[0, 1]] };
        let compared = compare(&characterize(&net).expect("valid"));
        let keys: Vec<&str> = compared.iter().map(|(k, _)| *k).collect();
        assert_eq!(keys, CHARACTERIZE_KEYS);
        let get = |key: &str| &compared.iter().find(|(k, _)| *k == key).expect("present").1;
        // Mean length 50 m is within 8.5..332 m; one branch has tortuosity 1 < 1.12.
        assert!(get("mean length").inside);
        assert_eq!(get("tortuosity").value, 1.0);
        assert!(!get("tortuosity").inside);
        assert!(!get("mean degree").inside);
    }
}
