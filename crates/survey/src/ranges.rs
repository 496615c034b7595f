//! The passages of real caves: the range over 17 surveyed caves of each statistic of their
//! stations' widths and heights, statistics computed for this project from KNdata-public
//! (ERC-Karst 2024) (`fixtures/passages/passage-ranges.json`, embedded at build time).

use std::collections::BTreeMap;

use serde::Deserialize;

const RANGES_JSON: &str = include_str!("../../../fixtures/passages/passage-ranges.json");

/// The range of one statistic over the surveyed caves.
#[derive(Debug, Clone, Copy, PartialEq, Deserialize)]
#[serde(from = "[f64; 2]")]
pub struct PassageRange {
    pub min: f64,
    pub max: f64,
}

impl From<[f64; 2]> for PassageRange {
    fn from([min, max]: [f64; 2]) -> Self {
        PassageRange { min, max }
    }
}

#[derive(Deserialize)]
struct RangesFile {
    ranges: BTreeMap<String, PassageRange>,
}

/// The ranges by statistic name (`median_width`, `sd_ln_width`, ...), as in the file.
pub fn passage_ranges() -> BTreeMap<String, PassageRange> {
    serde_json::from_str::<RangesFile>(RANGES_JSON).expect("the embedded passage ranges parse").ranges
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_nine_statistics_have_ranges() {
        let ranges = passage_ranges();
        for name in crate::statistics::NAMES {
            let r = ranges[name];
            assert!(r.min < r.max, "{name}");
        }
        assert_eq!(ranges["sd_ln_width"], PassageRange { min: 0.72, max: 1.313 });
    }
}
