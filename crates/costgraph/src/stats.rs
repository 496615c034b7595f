//! Distributions of the edge lengths and of every cost term, so that `inspect` can show what
//! drives the paths. Fixed-bin histograms: merging two is adding counts, so per-chunk
//! histograms merged in chunk order give the same result whatever the number of threads.

use serde::{Deserialize, Serialize};

/// Number of bins of every histogram.
pub const BINS: usize = 20;

/// A histogram of values over `[lo, hi]` with their count, mean and extremes.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Histogram {
    pub lo: f64,
    pub hi: f64,
    pub counts: Vec<u64>,
    pub min: f64,
    pub max: f64,
    pub sum: f64,
}

impl Histogram {
    pub fn new(lo: f64, hi: f64) -> Self {
        Histogram { lo, hi, counts: vec![0; BINS], min: f64::INFINITY, max: f64::NEG_INFINITY, sum: 0.0 }
    }

    pub fn add(&mut self, value: f64) {
        let width = (self.hi - self.lo).max(f64::MIN_POSITIVE);
        let bin = (((value - self.lo) / width) * BINS as f64).floor().clamp(0.0, (BINS - 1) as f64);
        self.counts[bin as usize] += 1;
        self.min = self.min.min(value);
        self.max = self.max.max(value);
        self.sum += value;
    }

    pub fn merge(&mut self, other: &Histogram) {
        for (a, b) in self.counts.iter_mut().zip(&other.counts) {
            *a += b;
        }
        self.min = self.min.min(other.min);
        self.max = self.max.max(other.max);
        self.sum += other.sum;
    }

    pub fn count(&self) -> u64 {
        self.counts.iter().sum()
    }

    pub fn mean(&self) -> f64 {
        self.sum / self.count().max(1) as f64
    }

    /// The `q` quantile, interpolated inside its bin and kept within [min, max] (a read
    /// histogram may hold min > max: `clamp` would panic on it).
    pub fn quantile(&self, q: f64) -> f64 {
        let total = self.count();
        if total == 0 {
            return f64::NAN;
        }
        let wanted = q.clamp(0.0, 1.0) * total as f64;
        let width = (self.hi - self.lo) / BINS as f64;
        let mut seen = 0.0;
        for (i, &c) in self.counts.iter().enumerate() {
            if c > 0 && seen + c as f64 >= wanted {
                let within = (wanted - seen) / c as f64;
                return (self.lo + width * (i as f64 + within)).max(self.min).min(self.max);
            }
            seen += c as f64;
        }
        self.max
    }

    /// One line: min, p10, median, p90, max, mean and a bar per bin.
    pub fn line(&self) -> String {
        let peak = self.counts.iter().copied().max().unwrap_or(0).max(1);
        let bars: String = self
            .counts
            .iter()
            .map(|&c| {
                const LEVELS: [char; 8] = ['▁', '▂', '▃', '▄', '▅', '▆', '▇', '█'];
                if c == 0 { ' ' } else { LEVELS[((c * 7) / peak) as usize] }
            })
            .collect();
        format!(
            "min {:.3}  p10 {:.3}  median {:.3}  p90 {:.3}  max {:.3}  mean {:.3}  [{bars}] over [{:.3}, {:.3}]",
            self.min,
            self.quantile(0.1),
            self.quantile(0.5),
            self.quantile(0.9),
            self.max,
            self.mean(),
            self.lo,
            self.hi
        )
    }
}

/// One named term's distribution over the edges of a cost set (mean of the term along each
/// edge, before its weight).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct TermStats {
    pub name: String,
    /// The weight the model gives the term.
    pub weight: f64,
    pub histogram: Histogram,
}

/// The distributions of one cost set.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct SetStats {
    pub water_table: Option<String>,
    pub terms: Vec<TermStats>,
    /// Edge cost divided by edge length.
    pub cost_per_metre: Histogram,
}

/// Everything `inspect` shows about the edges.
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
pub struct Summary {
    pub model: String,
    pub lengths: Option<Histogram>,
    pub sets: Vec<SetStats>,
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn quantiles_of_uniform_values() {
        let mut h = Histogram::new(0.0, 1.0);
        for i in 0..1000 {
            h.add(i as f64 / 999.0);
        }
        assert!((h.quantile(0.5) - 0.5).abs() < 0.01);
        assert!((h.quantile(0.9) - 0.9).abs() < 0.01);
        assert!((h.mean() - 0.5).abs() < 1e-9);
        let mut a = Histogram::new(0.0, 1.0);
        a.add(0.25);
        let mut b = Histogram::new(0.0, 1.0);
        b.add(0.75);
        a.merge(&b);
        assert_eq!((a.count(), a.min, a.max), (2, 0.25, 0.75));
    }
}
