//! Histogram classes chosen for the data. The bin width follows Freedman and Diaconis (1981),
//! h = 2 IQR n^(−1/3), which adapts to the spread and resists outliers; it needs a quartile
//! estimate, so below [`FEW`] values, or when the quartiles coincide, Sturges's rule (1926) sets
//! ⌈log₂ n⌉ + 1 classes over the range instead. The width is then rounded up to a nice number
//! (1, 2, 2.5 or 5 × 10^k) and the classes start at a multiple of it, so that their edges read
//! as round numbers on the axis.

use crate::ticks::nice_step;

/// Fewer values than this use Sturges's rule.
pub const FEW: usize = 20;
/// Never more classes than this, whatever the data.
const MOST: usize = 200;

/// Equal-width classes `[start + k·width, start + (k+1)·width)`, k < `count`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Bins {
    pub start: f64,
    pub width: f64,
    pub count: usize,
    pub rule: Rule,
}

/// Which rule set the width.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Rule {
    FreedmanDiaconis,
    Sturges,
}

impl Rule {
    pub fn name(self) -> &'static str {
        match self {
            Rule::FreedmanDiaconis => "Freedman–Diaconis",
            Rule::Sturges => "Sturges",
        }
    }
}

impl Bins {
    /// Classes for the finite values of `values`.
    pub fn choose(values: &[f64]) -> Bins {
        let mut v: Vec<f64> = values.iter().copied().filter(|x| x.is_finite()).collect();
        v.sort_by(f64::total_cmp);
        let (Some(&lo), Some(&hi)) = (v.first(), v.last()) else {
            return Bins { start: 0.0, width: 1.0, count: 1, rule: Rule::Sturges };
        };
        let n = v.len();
        let iqr = quantile(&v, 0.75) - quantile(&v, 0.25);
        let (raw, rule) = if n >= FEW && iqr > 0.0 {
            (2.0 * iqr / (n as f64).cbrt(), Rule::FreedmanDiaconis)
        } else {
            let classes = (n as f64).log2().ceil() + 1.0;
            ((hi - lo) / classes, Rule::Sturges)
        };
        let width = nice_step(raw.max((hi - lo) / MOST as f64));
        let start = (lo / width).floor() * width;
        let count = (((hi - start) / width).floor() as usize + 1).clamp(1, MOST + 1);
        Bins { start, width, count, rule }
    }

    /// The class of `x` (values past either end go to the end classes).
    pub fn index(&self, x: f64) -> usize {
        (((x - self.start) / self.width).floor().max(0.0) as usize).min(self.count - 1)
    }

    /// Number of finite values per class.
    pub fn counts(&self, values: &[f64]) -> Vec<usize> {
        let mut counts = vec![0; self.count];
        for &x in values.iter().filter(|x| x.is_finite()) {
            counts[self.index(x)] += 1;
        }
        counts
    }

    /// Left edge of class `k`.
    pub fn edge(&self, k: usize) -> f64 {
        self.start + k as f64 * self.width
    }
}

/// Linear-interpolation quantile of sorted values (numpy's default).
pub fn quantile(sorted: &[f64], q: f64) -> f64 {
    let pos = q * (sorted.len() - 1) as f64;
    let (i, f) = (pos.floor() as usize, pos.fract());
    match sorted.get(i + 1) {
        Some(next) => sorted[i] + (next - sorted[i]) * f,
        None => sorted[i],
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn nine_values_get_sturges_few_classes() {
        let lengths = [12.0, 40.0, 95.0, 130.0, 180.0, 260.0, 300.0, 410.0, 1030.0];
        let b = Bins::choose(&lengths);
        assert_eq!(b.rule, Rule::Sturges);
        // ⌈log₂ 9⌉ + 1 = 5 classes over 1018 m: 203.6 m, rounded up to 250 m: 0..1250, 5 classes.
        assert_eq!((b.start, b.width, b.count), (0.0, 250.0, 5));
        assert_eq!(b.counts(&lengths), vec![5, 3, 0, 0, 1]);
    }

    #[test]
    fn many_values_follow_freedman_diaconis() {
        // 1000 values evenly over [0, 100): IQR 50, n^(1/3) = 10, h = 10.
        let values: Vec<f64> = (0..1000).map(|i| f64::from(i) / 10.0).collect();
        let b = Bins::choose(&values);
        assert_eq!(b.rule, Rule::FreedmanDiaconis);
        assert_eq!((b.start, b.width, b.count), (0.0, 10.0, 10));
        assert!(b.counts(&values).iter().all(|&c| c == 100));
    }

    #[test]
    fn an_outlier_does_not_widen_the_classes() {
        let mut values: Vec<f64> = (0..1000).map(|i| f64::from(i) / 10.0).collect();
        values.push(1000.0);
        let b = Bins::choose(&values);
        assert_eq!(b.width, 10.0);
        assert_eq!(b.index(1000.0), b.count - 1);
        assert_eq!(b.counts(&values).iter().sum::<usize>(), 1001);
    }

    #[test]
    fn degenerate_samples_still_get_a_class() {
        assert_eq!(Bins::choose(&[]).count, 1);
        let same = Bins::choose(&[5.0; 30]);
        assert_eq!((same.rule, same.count), (Rule::Sturges, 1));
        assert_eq!(same.counts(&[5.0; 30]), vec![30]);
        assert_eq!(Bins::choose(&[f64::NAN, 2.0]).counts(&[f64::NAN, 2.0]), vec![1]);
    }
}
