//! Numbers for people: headlines and summaries round what they print.

/// `x` with about three significant digits and no trailing zeros: 10.000000000000002 → "10",
/// 0.012345 → "0.0123", 1234.5 → "1235", 2.5e-7 → "2.5e-7".
pub fn round(x: f64) -> String {
    if !x.is_finite() {
        return format!("{x}");
    }
    if x == 0.0 {
        return "0".into();
    }
    let magnitude = x.abs().log10().floor();
    if !(-4.0..9.0).contains(&magnitude) {
        return trim(format!("{x:.2e}"));
    }
    let decimals = (2.0 - magnitude).max(0.0) as usize;
    trim(format!("{x:.decimals$}"))
}

/// Drops trailing zeros of the fraction (and a bare point), in plain or exponent notation.
fn trim(text: String) -> String {
    let (mantissa, exponent) = match text.split_once('e') {
        Some((m, e)) => (m.to_string(), format!("e{e}")),
        None => (text, String::new()),
    };
    let mantissa = if mantissa.contains('.') {
        mantissa.trim_end_matches('0').trim_end_matches('.').to_string()
    } else {
        mantissa
    };
    mantissa + &exponent
}

#[cfg(test)]
mod tests {
    use super::round;

    #[test]
    fn three_significant_digits_without_trailing_zeros() {
        assert_eq!(round(10.000000000000002), "10");
        assert_eq!(round(0.012345), "0.0123");
        assert_eq!(round(1234.5), "1234");
        assert_eq!(round(1235.5), "1236");
        assert_eq!(round(2.5e-7), "2.5e-7");
        assert_eq!(round(-4.56789), "-4.57");
        assert_eq!(round(0.0), "0");
        assert_eq!(round(123456789012.0), "1.23e11");
        assert_eq!(round(f64::NAN), "NaN");
    }
}
