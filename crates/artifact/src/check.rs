//! Helpers for [`crate::Payload::validate`]: each returns an [`Invalid`] naming the field and
//! the value when a decoded number, index or count is out of what the consumers rely on.
//! Field names are built lazily (closures), so that validating millions of samples costs no
//! allocation when they are right.

use crate::envelope::Invalid;

/// Largest coordinate magnitude a payload may hold, metres: far beyond any scene (whose
/// coordinates are limited to 1e8 m, docs/limits.md), and small enough that squared distances
/// and sums of them stay finite.
pub const MAX_COORDINATE: f64 = 1e9;

/// `ok`, or `field` is wrong because of `problem`.
#[inline]
pub fn ensure(
    ok: bool,
    field: impl FnOnce() -> String,
    problem: impl FnOnce() -> String,
) -> Result<(), Invalid> {
    if ok { Ok(()) } else { Err(Invalid::new(field(), problem())) }
}

/// A position: every coordinate finite and within ±[`MAX_COORDINATE`].
#[inline]
pub fn position(field: impl FnOnce() -> String, p: &[f64]) -> Result<(), Invalid> {
    ensure(p.iter().all(|c| c.abs() <= MAX_COORDINATE), field, || {
        format!("{p:?} is not a finite position within ±{MAX_COORDINATE:e} m")
    })
}

/// A single-precision position, as [`position`].
#[inline]
pub fn position_f32(field: impl FnOnce() -> String, p: &[f32]) -> Result<(), Invalid> {
    ensure(p.iter().all(|c| (c.abs() as f64) <= MAX_COORDINATE), field, || {
        format!("{p:?} is not a finite position within ±{MAX_COORDINATE:e} m")
    })
}

/// A finite number within `[lo, hi]`.
#[inline]
pub fn within(field: impl FnOnce() -> String, value: f64, lo: f64, hi: f64) -> Result<(), Invalid> {
    ensure(value >= lo && value <= hi, field, || format!("{value} is not a finite number in [{lo}, {hi}]"))
}

/// A finite number > 0 and at most `hi`.
#[inline]
pub fn positive(field: impl FnOnce() -> String, value: f64, hi: f64) -> Result<(), Invalid> {
    ensure(value > 0.0 && value <= hi, field, || format!("{value} is not a finite number in (0, {hi}]"))
}

/// An index into a list of `len` items.
#[inline]
pub fn index(field: impl FnOnce() -> String, i: u64, len: usize) -> Result<(), Invalid> {
    ensure(i < len as u64, field, || format!("{i} is out of range: there are {len}"))
}

/// A list of `found` items where `expected` are needed.
#[inline]
pub fn count(field: impl FnOnce() -> String, found: usize, expected: usize) -> Result<(), Invalid> {
    ensure(found == expected, field, || format!("has {found} items, expected {expected}"))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn problems_name_the_field_and_the_value() {
        assert!(position(|| "p".into(), &[1.0, 2.0, 3.0]).is_ok());
        let e = position(|| "nodes[3].position".into(), &[1.0, f64::NAN, 3.0]).unwrap_err();
        assert_eq!(e.field, "nodes[3].position");
        assert!(e.problem.contains("NaN"), "{e:?}");
        assert!(position(|| "p".into(), &[1e308, 0.0, 0.0]).is_err());
        assert!(within(|| "x".into(), f64::NAN, 0.0, 1.0).is_err());
        assert!(positive(|| "r".into(), 0.0, 1.0).is_err());
        assert_eq!(index(|| "i".into(), 7, 7).unwrap_err().problem, "7 is out of range: there are 7");
        assert!(count(|| "c".into(), 2, 3).is_err());
    }
}
