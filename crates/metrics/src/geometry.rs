//! Geometric metrics on the full graph and its branches (spec §1 and §3 "Geometry"): branch
//! lengths, their mean / coefficient of variation / entropy, tortuosity and the orientation
//! entropy of the conduits.
//!
//! Histograms follow `numpy.histogram` with an explicit range exactly: bins are half-open except
//! the last one, which also holds the upper bound (a branch of maximal length, normalised to 100,
//! falls in bin 9), and a value is moved by one bin when its computed index disagrees with the
//! bin edges. Entropies are normalised by ln(number of bins), as `scipy.stats.entropy(base=nbins)`.

use crate::branches::{Branch, is_loop};
use crate::graph::FullGraph;

/// How many histogram bins an entropy uses.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Bins {
    /// Collon et al. 2017: 10 bins for lengths, 18 for orientations.
    Default,
    /// Sturges' rule: ⌈1 + log2(n)⌉ bins for n values.
    Sturges,
}

impl Bins {
    fn count(self, default: usize, n_values: usize) -> usize {
        match self {
            Bins::Default => default,
            Bins::Sturges => (1.0 + (n_values as f64).log2()).ceil() as usize,
        }
    }
}

/// 3D Euclidean distance.
pub(crate) fn distance(a: &[f64; 3], b: &[f64; 3]) -> f64 {
    let (dx, dy, dz) = (a[0] - b[0], a[1] - b[1], a[2] - b[2]);
    (dx * dx + dy * dy + dz * dz).sqrt()
}

/// Length of each branch: the sum of its edge lengths.
pub(crate) fn branch_lengths(g: &FullGraph, branches: &[Branch]) -> Vec<f64> {
    branches.iter().map(|b| b.windows(2).map(|w| distance(&g.pos[w[0]], &g.pos[w[1]])).sum()).collect()
}

/// Mean branch tortuosity `L_b / d_b`, skipping branches whose end nodes coincide (NaN if all do).
pub(crate) fn tortuosity(g: &FullGraph, branches: &[Branch], lengths: &[f64]) -> f64 {
    let values: Vec<f64> = branches
        .iter()
        .zip(lengths)
        .filter(|(b, _)| !is_loop(b))
        .filter_map(|(b, &len)| {
            let (first, last) = (&g.pos[b[0]], &g.pos[b[b.len() - 1]]);
            let d = distance(first, last);
            (first != last && d != 0.0).then_some(len / d)
        })
        .collect();
    mean(&values)
}

/// Arithmetic mean (NaN for no value).
pub(crate) fn mean(values: &[f64]) -> f64 {
    values.iter().sum::<f64>() / values.len() as f64
}

/// Sample standard deviation (N − 1) over the mean; 0 for fewer than two values.
pub(crate) fn coefficient_of_variation(values: &[f64]) -> f64 {
    if values.len() < 2 {
        return 0.0;
    }
    let m = mean(values);
    let squares: f64 = values.iter().map(|v| (v - m) * (v - m)).sum();
    (squares / (values.len() - 1) as f64).sqrt() / m
}

/// Entropy of the non-zero branch lengths normalised to `L / max L · 100`, on [0, 100].
pub(crate) fn length_entropy(lengths: &[f64], bins: Bins) -> f64 {
    let nonzero: Vec<f64> = lengths.iter().copied().filter(|&l| l != 0.0).collect();
    let max = nonzero.iter().copied().fold(0.0, f64::max);
    let normalised: Vec<f64> = nonzero.iter().map(|l| l / max * 100.0).collect();
    if normalised.len() < 2 {
        return 0.0;
    }
    let n_bins = bins.count(10, normalised.len());
    entropy(&histogram(&normalised, None, n_bins, 100.0), n_bins)
}

/// Entropy of the axial azimuths of the non-vertical edges, weighted by projected length.
pub(crate) fn orientation_entropy(g: &FullGraph, bins: Bins) -> f64 {
    let (azimuths, weights) = azimuths(g);
    if azimuths.len() < 2 {
        return 0.0;
    }
    let n_bins = bins.count(18, azimuths.len());
    entropy(&histogram(&azimuths, Some(&weights), n_bins, 180.0), n_bins)
}

/// Projected conduit length per 10° azimuth class (N–S first): the histogram behind the
/// orientation entropy, and the petals of the rose diagram.
pub(crate) fn orientation_histogram(g: &FullGraph) -> Vec<f64> {
    let (azimuths, weights) = azimuths(g);
    histogram(&azimuths, Some(&weights), 18, 180.0)
}

/// Axial azimuth and projected length of every non-vertical edge.
fn azimuths(g: &FullGraph) -> (Vec<f64>, Vec<f64>) {
    g.edges
        .iter()
        .filter_map(|&[u, v]| {
            let (dx, dy) = (g.pos[u][0] - g.pos[v][0], g.pos[u][1] - g.pos[v][1]);
            let l2d = (dx * dx + dy * dy).sqrt();
            (l2d != 0.0).then(|| (azimuth(dx, dy, l2d), l2d))
        })
        .unzip()
}

/// Axial azimuth in degrees, in [0, 180): N–S = 0, E–W = 90.
///
/// Directions whose exact azimuth is a multiple of 45° get it exactly: they sit on bin edges
/// (Sturges' bins often have edges at 45° and 135°), where libm's `asin(1/√2)` rounds one ulp
/// below 45° while numpy's vectorised `arcsin` — hence karstnet — lands on 45°.
fn azimuth(dx: f64, dy: f64, l2d: f64) -> f64 {
    let to_degrees = |radians: f64| radians * (180.0 / std::f64::consts::PI);
    let a = if dx == 0.0 {
        0.0
    } else if dy == 0.0 {
        90.0
    } else if dx.abs() == dy.abs() {
        if dx * dy > 0.0 { 45.0 } else { 135.0 }
    } else if dx * dy > 0.0 {
        to_degrees((dx.abs() / l2d).asin())
    } else {
        90.0 + to_degrees((dx.abs() / l2d).acos())
    };
    a % 180.0
}

/// `numpy.histogram(values, bins=n_bins, range=(0, upper), weights=weights)` counts.
fn histogram(values: &[f64], weights: Option<&[f64]>, n_bins: usize, upper: f64) -> Vec<f64> {
    let mut counts = vec![0.0; n_bins];
    for (i, &v) in values.iter().enumerate() {
        if let Some(bin) = bin_index(v, n_bins, upper) {
            counts[bin] += weights.map_or(1.0, |w| w[i]);
        }
    }
    counts
}

/// numpy's bin of `x` among `n_bins` equal bins on [0, upper]; `None` outside the range.
fn bin_index(x: f64, n_bins: usize, upper: f64) -> Option<usize> {
    if !(0.0..=upper).contains(&x) {
        return None;
    }
    let edge = |i: usize| {
        if i == n_bins { upper } else { i as f64 * (upper / n_bins as f64) }
    };
    let mut bin = (((x / upper) * n_bins as f64) as usize).min(n_bins - 1);
    if x < edge(bin) {
        bin -= 1;
    }
    if bin != n_bins - 1 && x >= edge(bin + 1) {
        bin += 1;
    }
    Some(bin)
}

/// Shannon entropy of a histogram, in base `n_bins`.
fn entropy(counts: &[f64], n_bins: usize) -> f64 {
    let total: f64 = counts.iter().sum();
    let nats: f64 = counts
        .iter()
        .filter(|&&c| c > 0.0)
        .map(|&c| {
            let p = c / total;
            -p * p.ln()
        })
        .sum();
    nats / (n_bins as f64).ln()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn bins_follow_numpy_edges() {
        assert_eq!(bin_index(0.0, 10, 100.0), Some(0));
        assert_eq!(bin_index(10.0, 10, 100.0), Some(1));
        assert_eq!(bin_index(9.999_999_999_999_998, 10, 100.0), Some(0));
        assert_eq!(bin_index(100.0, 10, 100.0), Some(9));
        assert_eq!(bin_index(179.9, 18, 180.0), Some(17));
        assert_eq!(bin_index(100.5, 10, 100.0), None);
        // 3 Sturges bins on [0, 100]: edges 0, 33.33.., 66.66.., 100.
        assert_eq!(bin_index(100.0 / 3.0, 3, 100.0), Some(1));
    }

    #[test]
    fn azimuths_are_axial() {
        for (dx, dy, expected) in [
            (0.0, 1.0, 0.0),
            (0.0, -1.0, 0.0),
            (1.0, 0.0, 90.0),
            (-1.0, 0.0, 90.0),
            (1.0, 1.0, 45.0),
            (-1.0, -1.0, 45.0),
            (-1.0, 1.0, 135.0),
            (1.0, -1.0, 135.0),
            (3.0, 3.0, 45.0),
        ] {
            assert_eq!(azimuth(dx, dy, (dx * dx + dy * dy).sqrt()), expected, "({dx}, {dy})");
        }
    }

    #[test]
    fn azimuths_in_between() {
        let a = azimuth(1.0, 3f64.sqrt(), 2.0);
        assert!((a - 30.0).abs() < 1e-12, "{a}");
        let a = azimuth(-1.0, 3f64.sqrt(), 2.0);
        assert!((a - 150.0).abs() < 1e-12, "{a}");
    }

    #[test]
    fn length_entropy_puts_the_maximum_in_the_last_bin() {
        // Normalised lengths 50 and 100: two bins with one value each -> log10(2).
        let h = length_entropy(&[1.0, 2.0, 0.0], Bins::Default);
        assert!((h - 2f64.ln() / 10f64.ln()).abs() < 1e-15);
        assert_eq!(length_entropy(&[3.0, 0.0], Bins::Default), 0.0);
        assert_eq!(length_entropy(&[3.0, 3.0], Bins::Default), 0.0);
    }

    #[test]
    fn coefficient_of_variation_uses_the_sample_std() {
        assert_eq!(coefficient_of_variation(&[4.0]), 0.0);
        let cv = coefficient_of_variation(&[1.0, 3.0]);
        assert!((cv - 2f64.sqrt() / 2.0).abs() < 1e-15);
    }
}
