//! The memory budget of a run and the work estimates checked against it.
//!
//! Before each large allocation a stage estimates, from the scene (and the sizes of its inputs),
//! the memory it is about to need: samples, edges, sdf primitives, mesh triangles, catchment
//! cells. Above the budget it refuses with the estimate, the scene field that drives it and a
//! value of that field that would fit ([`Budget::check`]), instead of aborting on an
//! allocation or swapping for hours. The budget is a property of the machine, not of the
//! scene: it is set on the command line (`--max-memory`, default [`DEFAULT_BYTES`]), travels
//! with the loaded scene ([`crate::Scene::budget`]) and is in no artifact key.

use std::fmt;

/// The default budget: 16 GiB, two thirds of the 24 GiB machine karstgen is sized for, leaving
/// room for the inputs already in memory, the system and the artifact being written.
pub const DEFAULT_BYTES: u64 = 16 << 30;

/// Bytes of the MB (MiB) the output budgets and `export.gltf_max_mb` are given in.
pub const MB: f64 = (1u64 << 20) as f64;

/// How much memory a stage may plan to use.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Budget {
    pub bytes: u64,
}

impl Default for Budget {
    fn default() -> Self {
        Budget { bytes: DEFAULT_BYTES }
    }
}

impl fmt::Display for Budget {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(&bytes(self.bytes as f64))
    }
}

/// A memory size that cannot be read (`--max-memory`).
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum SizeError {
    #[error("\"{0}\" is not a size such as 16G or 512M")]
    NotASize(String),
    #[error("\"{0}\": unknown unit (use K, M, G or T)")]
    Unit(String),
    #[error("\"{0}\" is not a usable memory size")]
    Unusable(String),
}

impl std::str::FromStr for Budget {
    type Err = SizeError;

    /// `16G`, `512M`, `1.5GiB`, `2 GB` or plain bytes; K, M, G, T are powers of 1024.
    fn from_str(text: &str) -> Result<Budget, SizeError> {
        let t = text.trim();
        let split = t.find(|c: char| !(c.is_ascii_digit() || c == '.')).unwrap_or(t.len());
        let (number, unit) = t.split_at(split);
        let value: f64 = number.parse().map_err(|_| SizeError::NotASize(text.into()))?;
        let unit = unit.trim().trim_end_matches("iB").trim_end_matches('B').to_ascii_uppercase();
        let scale = match unit.as_str() {
            "" => 1.0,
            "K" => 1024.0,
            "M" => 1024f64.powi(2),
            "G" => 1024f64.powi(3),
            "T" => 1024f64.powi(4),
            _ => return Err(SizeError::Unit(text.into())),
        };
        let bytes = value * scale;
        if !(bytes >= 1.0 && bytes < 2f64.powi(63)) {
            return Err(SizeError::Unusable(text.into()));
        }
        Ok(Budget { bytes: bytes as u64 })
    }
}

/// What a stage is about to allocate, and the scene field that drives it.
#[derive(Debug, Clone, PartialEq)]
pub struct Estimate {
    /// What is counted, for people: "3.6e9 samples".
    pub what: String,
    /// Bytes it needs.
    pub bytes: f64,
    /// The scene field that drives it (`sampling.radius`).
    pub field: String,
    /// The field's value now.
    pub value: f64,
}

/// A stage that would need more memory than the budget allows.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[error("{}", self.message())]
pub struct OverBudget {
    pub estimate: Estimate,
    pub budget: Budget,
    /// A value of the field that would fit, when one does.
    pub fits: Option<f64>,
}

impl OverBudget {
    fn message(&self) -> String {
        let e = &self.estimate;
        let advice = match self.fits {
            Some(v) => format!("{} = {} would fit", e.field, short(v)),
            None => format!("no value of {} alone fits: change the scene's other sizes too", e.field),
        };
        format!(
            "{} = {} means about {} ({}), more than the memory budget of {} (raise it with --max-memory \
             if this machine has the memory): {advice}",
            e.field,
            short(e.value),
            e.what,
            bytes(e.bytes),
            self.budget
        )
    }
}

/// Whether larger values of a field cost less (radii, cells) or more (counts).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Cheaper {
    Larger,
    Smaller,
}

impl Budget {
    /// Ok when `estimate` fits; otherwise the refusal, with the value of the field that would
    /// fit found by bisection on `bytes_at` (the estimate's bytes for another value of the
    /// field, everything else unchanged), rounded to two significant digits on the safe side.
    /// `integer` fields get an integer value.
    pub fn check(
        &self,
        estimate: Estimate,
        cheaper: Cheaper,
        integer: bool,
        bytes_at: impl Fn(f64) -> f64,
    ) -> Result<(), OverBudget> {
        if estimate.bytes <= self.bytes as f64 {
            return Ok(());
        }
        let fits = self.fitting_value(estimate.value, cheaper, integer, &bytes_at);
        Err(OverBudget { estimate, budget: *self, fits })
    }

    fn fitting_value(
        &self,
        value: f64,
        cheaper: Cheaper,
        integer: bool,
        bytes_at: &dyn Fn(f64) -> f64,
    ) -> Option<f64> {
        let budget = self.bytes as f64;
        let fits = |v: f64| bytes_at(v) <= budget;
        // Walk by factors 2, 4, 16, 256…, squaring the factor each step, until a value fits
        // (a handful of estimates even from 1e-300), then bisect between the last two on a
        // log scale.
        let step = |v: f64, factor: f64| match cheaper {
            Cheaper::Larger => v * factor,
            Cheaper::Smaller => v / factor,
        };
        let (mut bad, mut factor) = (value, 2.0f64);
        let mut good = step(value, factor);
        while !fits(good) {
            factor = (factor * factor).min(1e100);
            (bad, good) = (good, step(good, factor));
            if !(good.is_finite() && good > 0.0) {
                return None;
            }
        }
        for _ in 0..24 {
            let mid = (bad.ln() + (good.ln() - bad.ln()) / 2.0).exp();
            if fits(mid) { good = mid } else { bad = mid }
        }
        let rounded = round_safe(good, cheaper, integer);
        fits(rounded).then_some(rounded)
    }
}

/// `v` to two significant digits, rounded towards the cheaper side.
fn round_safe(v: f64, cheaper: Cheaper, integer: bool) -> f64 {
    if integer {
        return match cheaper {
            Cheaper::Larger => v.ceil(),
            Cheaper::Smaller => v.floor(),
        };
    }
    let unit = 10f64.powf(v.log10().floor() - 1.0);
    match cheaper {
        Cheaper::Larger => (v / unit).ceil() * unit,
        Cheaper::Smaller => (v / unit).floor() * unit,
    }
}

/// A number with about three significant digits.
fn short(v: f64) -> String {
    if v == 0.0 || (1e-3..1e6).contains(&v.abs()) {
        let text = format!("{v:.4}");
        let text = text.trim_end_matches('0').trim_end_matches('.');
        text.to_string()
    } else {
        format!("{v:.2e}")
    }
}

/// Bytes for people: "290 GB".
pub fn bytes(b: f64) -> String {
    const UNITS: [&str; 6] = ["B", "KiB", "MiB", "GiB", "TiB", "PiB"];
    let mut value = b;
    for unit in UNITS {
        if value < 1024.0 {
            let decimals = if value >= 100.0 {
                0
            } else if value >= 10.0 {
                1
            } else {
                2
            };
            let text = format!("{value:.decimals$}");
            let text =
                if text.contains('.') { text.trim_end_matches('0').trim_end_matches('.') } else { &text };
            return format!("{text} {unit}");
        }
        value /= 1024.0;
    }
    format!("{b:.2e} B")
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sizes_parse_with_binary_units() {
        assert_eq!("16G".parse::<Budget>().unwrap().bytes, 16 << 30);
        assert_eq!("512 MiB".parse::<Budget>().unwrap().bytes, 512 << 20);
        assert_eq!("1.5GB".parse::<Budget>().unwrap().bytes, 3 << 29);
        assert_eq!("4096".parse::<Budget>().unwrap().bytes, 4096);
        assert!("lots".parse::<Budget>().is_err());
        assert!("0".parse::<Budget>().is_err());
        assert!("3X".parse::<Budget>().is_err());
    }

    #[test]
    fn a_refusal_gives_a_value_that_fits() {
        // 100 bytes per sample, samples ∝ radius⁻³ (1e6 at radius 1).
        let bytes_at = |r: f64| 100.0 * 1e6 / (r * r * r);
        let budget = Budget { bytes: 1 << 30 };
        let estimate = |r: f64| Estimate {
            what: format!("{:.2e} samples", 1e6 / (r * r * r)),
            bytes: bytes_at(r),
            field: "sampling.radius".into(),
            value: r,
        };
        assert!(budget.check(estimate(1.0), Cheaper::Larger, false, bytes_at).is_ok());
        let err = budget.check(estimate(0.01), Cheaper::Larger, false, bytes_at).unwrap_err();
        let fits = err.fits.unwrap();
        assert!(bytes_at(fits) <= (1u64 << 30) as f64 && fits < 0.5, "{fits}");
        let message = err.to_string();
        assert!(message.contains("sampling.radius = 0.01 means about 1.00e12 samples"), "{message}");
        assert!(message.contains("more than the memory budget of 1 GiB"), "{message}");
        assert!(message.contains(&format!("sampling.radius = {} would fit", short(fits))), "{message}");
        // A count that grows the estimate: the advice is a smaller integer.
        let per_k = |k: f64| k * 1e8;
        let e =
            Estimate { what: "edges".into(), bytes: per_k(40.0), field: "costgraph.k".into(), value: 40.0 };
        let err = budget.check(e, Cheaper::Smaller, true, per_k).unwrap_err();
        assert_eq!(err.fits, Some(10.0));
    }
}
