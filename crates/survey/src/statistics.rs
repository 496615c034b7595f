//! The nine statistics of a survey's widths and heights (issue 39's table), as
//! `passage-ranges.json` defines them for the real caves: over the stations that carry both a
//! width and a height (here: not shafts, not within a passage width of a junction), medians,
//! spreads of the logarithms, percentiles of width / height (linear between order statistics),
//! and the Pearson correlation of ln width (ln height) between adjacent stations of one conduit.

use std::collections::BTreeMap;

use crate::payload::{PassageStatistic, Station};
use crate::ranges::PassageRange;

/// The statistics' names, as in passage-ranges.json.
pub const NAMES: [&str; 9] = [
    "median_width",
    "median_height",
    "sd_ln_width",
    "sd_ln_height",
    "median_wh",
    "p10_wh",
    "p90_wh",
    "lag1_ln_width",
    "lag1_ln_height",
];

/// Whether a station counts in the statistics.
pub fn counts(s: &Station) -> bool {
    !s.shaft && !s.junction && s.width > 0.0 && s.height > 0.0
}

/// The nine statistics of `stations` (in conduit and station order) beside `ranges`.
pub fn statistics(
    stations: &[Station],
    ranges: &BTreeMap<String, PassageRange>,
) -> BTreeMap<String, PassageStatistic> {
    let counted: Vec<&Station> = stations.iter().filter(|s| counts(s)).collect();
    let width: Vec<f64> = counted.iter().map(|s| s.width).collect();
    let height: Vec<f64> = counted.iter().map(|s| s.height).collect();
    let wh: Vec<f64> = counted.iter().map(|s| s.width / s.height).collect();
    let ln = |v: &[f64]| v.iter().map(|x| x.ln()).collect::<Vec<f64>>();
    let pairs: Vec<[&Station; 2]> = stations
        .windows(2)
        .filter(|w| w[0].conduit == w[1].conduit && w[1].station == w[0].station + 1)
        .filter(|w| counts(&w[0]) && counts(&w[1]))
        .map(|w| [&w[0], &w[1]])
        .collect();
    let lag1 = |f: fn(&Station) -> f64| {
        let (a, b): (Vec<f64>, Vec<f64>) = pairs.iter().map(|[x, y]| (f(x).ln(), f(y).ln())).unzip();
        pearson(&a, &b)
    };
    let values = [
        percentile(&width, 0.5),
        percentile(&height, 0.5),
        sd(&ln(&width)),
        sd(&ln(&height)),
        percentile(&wh, 0.5),
        percentile(&wh, 0.1),
        percentile(&wh, 0.9),
        lag1(|s| s.width),
        lag1(|s| s.height),
    ];
    NAMES
        .iter()
        .zip(values)
        .map(|(name, value)| {
            let PassageRange { min, max } = ranges[*name];
            let inside = value.is_some_and(|v| (min..=max).contains(&v));
            (name.to_string(), PassageStatistic { value, min, max, inside })
        })
        .collect()
}

/// The q-quantile, linear between order statistics (numpy's default); None when empty.
pub fn percentile(values: &[f64], q: f64) -> Option<f64> {
    if values.is_empty() {
        return None;
    }
    let mut v = values.to_vec();
    v.sort_by(f64::total_cmp);
    let x = q * (v.len() - 1) as f64;
    let (i, f) = (x.floor() as usize, x.fract());
    Some(if i + 1 < v.len() { v[i] + (v[i + 1] - v[i]) * f } else { v[i] })
}

/// Population standard deviation; None with fewer than two values.
pub fn sd(values: &[f64]) -> Option<f64> {
    if values.len() < 2 {
        return None;
    }
    let n = values.len() as f64;
    let mean = values.iter().sum::<f64>() / n;
    Some((values.iter().map(|v| (v - mean).powi(2)).sum::<f64>() / n).sqrt())
}

/// Pearson's correlation of paired values; None with fewer than three pairs or no spread.
pub fn pearson(a: &[f64], b: &[f64]) -> Option<f64> {
    if a.len() < 3 {
        return None;
    }
    let n = a.len() as f64;
    let (ma, mb) = (a.iter().sum::<f64>() / n, b.iter().sum::<f64>() / n);
    let cov: f64 = a.iter().zip(b).map(|(x, y)| (x - ma) * (y - mb)).sum();
    let va: f64 = a.iter().map(|x| (x - ma).powi(2)).sum();
    let vb: f64 = b.iter().map(|y| (y - mb).powi(2)).sum();
    (va > 0.0 && vb > 0.0).then(|| cov / (va * vb).sqrt())
}

#[cfg(test)]
mod tests {
    use super::*;
    use karst_skeleton::{ConduitType, Zone};

    fn station(conduit: u32, station: u32, width: f64, height: f64) -> Station {
        Station {
            conduit,
            station,
            position: [0.0; 3],
            width,
            height,
            area: width * height,
            kind: ConduitType::Canyon,
            zone: Zone::Vadose,
            shaft: false,
            junction: false,
        }
    }

    #[test]
    fn quantiles_spreads_and_correlations_by_hand() {
        assert_eq!(percentile(&[4.0, 1.0, 3.0, 2.0], 0.5), Some(2.5));
        assert_eq!(percentile(&[1.0, 2.0, 3.0, 4.0, 5.0], 0.1), Some(1.4));
        assert_eq!(sd(&[1.0, 3.0]), Some(1.0));
        assert_eq!(pearson(&[1.0, 2.0, 3.0], &[2.0, 4.0, 6.0]), Some(1.0));
        assert_eq!(pearson(&[1.0, 2.0, 3.0], &[3.0, 2.0, 1.0]), Some(-1.0));
        assert_eq!(pearson(&[1.0, 1.0, 1.0], &[3.0, 2.0, 1.0]), None);
    }

    #[test]
    fn adjacent_pairs_stay_in_one_conduit_and_skip_excluded_stations() {
        let ranges = crate::ranges::passage_ranges();
        let mut stations: Vec<Station> = (1..=4).map(|k| station(1, k, k as f64, 1.0)).collect();
        stations.extend((1..=4).map(|k| station(2, k, 10.0 / k as f64, 1.0)));
        // Lag-one pairs within conduits: (1,2), (2,3), (3,4) and (10,5), (5,3.33), (3.33,2.5).
        let both = statistics(&stations, &ranges);
        stations[5].junction = true;
        let without = statistics(&stations, &ranges);
        assert_ne!(both["lag1_ln_width"].value, without["lag1_ln_width"].value);
        assert_eq!(without["median_height"].value, Some(1.0));
        assert!(!without["sd_ln_height"].inside);
        stations.iter_mut().for_each(|s| s.shaft = true);
        assert_eq!(statistics(&stations, &ranges)["median_width"].value, None);
    }
}
