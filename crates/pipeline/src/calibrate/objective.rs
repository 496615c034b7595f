//! The distance between a network and the target cave: each of karstnet's ten
//! `characterize_graph()` metrics differs from the target's by some amount, divided by the
//! width of that metric's range over real caves (Collon et al. 2017), so that a metric counts by
//! how far it moves across real caves, not by its unit; the distance is the root mean square of
//! these normalised differences. A metric the network leaves undefined (NaN, e.g. the
//! tortuosity of a network made only of loops) counts as
//! [`karst_metrics::aim::UNDEFINED`]; a metric the target
//! leaves undefined is left out. A candidate's distance is the median over its seeds.

use karst_metrics::aim;

use super::evaluate::MetricVector;

pub use karst_metrics::aim::median;

/// The target and the width of each metric's real-cave range.
pub struct Objective {
    target: MetricVector,
    width: MetricVector,
}

impl Objective {
    pub fn new(target: MetricVector) -> Objective {
        Objective { target, width: aim::widths() }
    }

    /// The distance of a network with `metrics` to the target (`karst_metrics::aim::distance`).
    pub fn distance(&self, metrics: &MetricVector) -> f64 {
        aim::distance(metrics, &self.target, &self.width)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_distance_is_zero_on_the_target_and_counts_ranges() {
        let target: MetricVector = [20.0, 1.0, 0.4, 1.3, 0.99, 12.0, 0.3, 2.4, 0.5, -0.2];
        let o = Objective::new(target);
        assert_eq!(o.distance(&target), 0.0);
        let mut one_range_off = target;
        one_range_off[6] += o.width[6];
        assert!((o.distance(&one_range_off) - (0.1f64).sqrt()).abs() < 1e-12);
        let mut undefined = target;
        undefined[3] = f64::NAN;
        assert!((o.distance(&undefined) - (0.1f64).sqrt()).abs() < 1e-12);
    }

    #[test]
    fn a_metric_the_target_leaves_undefined_is_left_out() {
        let mut target: MetricVector = [20.0, 1.0, 0.4, 1.3, 0.99, 12.0, 0.3, 2.4, 0.5, -0.2];
        target[3] = f64::NAN;
        let o = Objective::new(target);
        let mut m = target;
        m[3] = 5.0;
        assert_eq!(o.distance(&m), 0.0);
    }

    #[test]
    fn median_of_odd_and_even_counts() {
        assert_eq!(median([3.0, 1.0, 2.0]), 2.0);
        assert_eq!(median([4.0, 1.0, 2.0, f64::NAN, 3.0]), 2.5);
        assert!(median([f64::NAN]).is_nan());
    }
}
