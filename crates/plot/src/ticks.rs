//! Numbers for people: "nice" tick steps (1, 2 or 5 times a power of ten), the ticks of an
//! interval, and numbers printed with no more digits than their step needs.

/// The nice step (1, 2, 2.5 or 5 × 10^k) nearest above `raw`; 1 for a step that is not positive
/// and finite.
pub fn nice_step(raw: f64) -> f64 {
    if !(raw.is_finite() && raw > 0.0) {
        return 1.0;
    }
    let power = 10f64.powf(raw.log10().floor());
    let mantissa = raw / power;
    let nice = [1.0, 2.0, 2.5, 5.0, 10.0].into_iter().find(|&m| mantissa <= m * (1.0 + 1e-9)).unwrap_or(10.0);
    nice * power
}

/// Ticks at multiples of a nice step inside [lo, hi], about `target` of them.
pub fn ticks(lo: f64, hi: f64, target: usize) -> Vec<f64> {
    if !(lo.is_finite() && hi.is_finite()) {
        return Vec::new();
    }
    let (lo, hi) = (lo.min(hi), lo.max(hi));
    if hi - lo <= f64::EPSILON * hi.abs().max(1.0) {
        return vec![lo];
    }
    let step = nice_step((hi - lo) / target.max(1) as f64);
    let first = (lo / step - 1e-9).ceil() as i64;
    let last = (hi / step + 1e-9).floor() as i64;
    (first..=last).map(|k| snap(k as f64 * step, step)).collect()
}

/// `v` printed with the decimals a step of `step` needs (at most 6), "-0" shown as "0".
pub fn format(v: f64, step: f64) -> String {
    let power = if step > 0.0 && step.is_finite() { (step.log10() + 1e-9).floor() } else { 0.0 };
    let decimals = (-power).clamp(0.0, 6.0) as usize;
    // 2.5 and 0.25 need one digit more than their power shows; 25 and 250 do not.
    let decimals = decimals + usize::from(decimals < 6 && power < 1.0 && is_quarter(step));
    let text = format!("{v:.decimals$}");
    if text.trim_start_matches('-').chars().all(|c| c == '0' || c == '.') {
        text.trim_start_matches('-').into()
    } else {
        text
    }
}

/// `v` with three significant digits (integers of up to six digits in full): for values
/// printed on their own, such as a legend's figure.
pub fn human(v: f64) -> String {
    if !v.is_finite() {
        return "undefined".into();
    }
    let a = v.abs();
    if a >= 100.0 || a == 0.0 {
        return format!("{v:.0}");
    }
    let decimals = (2.0 - a.log10().floor()).clamp(0.0, 6.0) as usize;
    let text = format!("{v:.decimals$}");
    if text.contains('.') { text.trim_end_matches('0').trim_end_matches('.').into() } else { text }
}

/// `v` with up to three decimals, trailing zeros dropped: for coordinates and sizes given by
/// the user (369.7 stays 369.7, 0.10000000000000001 becomes 0.1).
pub fn plain(v: f64) -> String {
    let text = format!("{v:.3}");
    let text = text.trim_end_matches('0').trim_end_matches('.');
    if text == "-0" { "0".into() } else { text.into() }
}

/// Whether a nice step is 2.5 × 10^k, which needs one more decimal than its power shows.
fn is_quarter(step: f64) -> bool {
    let mantissa = step / 10f64.powf((step.log10() + 1e-9).floor());
    (mantissa - 2.5).abs() < 1e-6
}

/// Rounds a multiple of `step` so that 0.1 × 3 prints as 0.3 and −0 as 0.
fn snap(v: f64, step: f64) -> f64 {
    let r = (v / step).round() * step;
    if r.abs() < step * 1e-9 { 0.0 } else { r }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn steps_are_nice() {
        assert_eq!(nice_step(0.7), 1.0);
        assert_eq!(nice_step(1.3), 2.0);
        assert_eq!(nice_step(2.2), 2.5);
        assert_eq!(nice_step(37.0), 50.0);
        assert_eq!(nice_step(100.0), 100.0);
        assert!((nice_step(0.012) - 0.02).abs() < 1e-12);
    }

    #[test]
    fn ticks_cover_the_interval_at_nice_multiples() {
        assert_eq!(ticks(0.0, 10.0, 5), vec![0.0, 2.0, 4.0, 6.0, 8.0, 10.0]);
        assert_eq!(ticks(13.0, 97.0, 4), vec![25.0, 50.0, 75.0]);
        assert_eq!(ticks(-1.0, 1.0, 4), vec![-1.0, -0.5, 0.0, 0.5, 1.0]);
        assert_eq!(ticks(3.0, 3.0, 5), vec![3.0]);
        assert!(ticks(f64::NAN, 1.0, 5).is_empty());
    }

    #[test]
    fn numbers_carry_only_the_digits_they_need() {
        assert_eq!(format(200.0, 100.0), "200");
        assert_eq!(format(0.30000000000000004, 0.1), "0.3");
        assert_eq!(format(2.5, 2.5), "2.5");
        assert_eq!(format(575.0, 25.0), "575");
        assert_eq!(format(0.75, 0.25), "0.75");
        assert_eq!(format(-0.0, 1.0), "0");
        assert_eq!(human(10.000000000000002), "10");
        assert_eq!(human(0.123456), "0.123");
        assert_eq!(human(2459.4), "2459");
        assert_eq!(human(f64::NAN), "undefined");
        assert_eq!(plain(369.7), "369.7");
        assert_eq!(plain(0.1 + 0.2), "0.3");
        assert_eq!(plain(120.0), "120");
        assert_eq!(plain(-0.0001), "0");
    }
}
