//! Semantic comparison of two artifacts of the same kind.
//!
//! Both payloads are read through their stage's types (so a corrupt file is an error, not a
//! difference) and compared field by field: array lengths (counts of samples, edges, nodes,
//! conduits, triangles...), non-numeric values, and numbers within a relative tolerance. The
//! report gives, per top-level field, how many values differ and the largest difference.

use std::collections::BTreeMap;
use std::fmt::Write;
use std::path::Path;

use serde_json::Value;

use karst_artifact::{StageId, read_header};
use karst_stage::StageError;

/// Differences of one top-level field.
#[derive(Debug, Default, Clone, PartialEq)]
pub struct FieldDiff {
    /// Values compared.
    pub compared: u64,
    /// Values that differ beyond tolerance (numbers) or at all (anything else).
    pub differing: u64,
    /// Array length mismatches, as "path: a vs b".
    pub counts: Vec<String>,
    /// Largest numeric difference and where.
    pub largest: Option<(f64, String)>,
}

/// The comparison of two artifacts.
#[derive(Debug, Clone, PartialEq)]
pub struct Report {
    pub kind: StageId,
    pub fields: BTreeMap<String, FieldDiff>,
}

impl Report {
    /// True when the artifacts differ beyond tolerance.
    pub fn differs(&self) -> bool {
        self.fields.values().any(|f| f.differing > 0 || !f.counts.is_empty())
    }

    /// Human-readable summary, one line per field.
    pub fn summary(&self) -> String {
        let mut text = String::new();
        for (name, f) in &self.fields {
            let _ = write!(text, "  {name}: {} values, {} differ", f.compared, f.differing);
            if let Some((d, at)) = &f.largest {
                let _ = write!(text, ", largest difference {d:.3e} at {at}");
            }
            for c in &f.counts {
                let _ = write!(text, "; count {c}");
            }
            text.push('\n');
        }
        text
    }
}

/// Compares artifacts `a` and `b`; numbers are equal when |x − y| ≤ tol · max(1, |x|, |y|).
pub fn diff(a: &Path, b: &Path, tol: f64) -> Result<Report, StageError> {
    let (kind_a, kind_b) = (read_header(a)?.kind, read_header(b)?.kind);
    if kind_a != kind_b {
        return Err(StageError::input(format!(
            "{} is a {} artifact but {} is a {} artifact",
            a.display(),
            kind_a.row().kind,
            b.display(),
            kind_b.row().kind
        )));
    }
    let stage = crate::registry::stage(kind_a);
    let (va, vb) = (stage.payload_value(a)?, stage.payload_value(b)?);
    let mut fields = BTreeMap::new();
    match (&va, &vb) {
        (Value::Object(ma), Value::Object(mb)) => {
            for key in ma.keys().chain(mb.keys()) {
                let f: &mut FieldDiff = fields.entry(key.clone()).or_default();
                if f.compared == 0 && f.counts.is_empty() {
                    compare(
                        ma.get(key).unwrap_or(&Value::Null),
                        mb.get(key).unwrap_or(&Value::Null),
                        key,
                        tol,
                        f,
                    );
                }
            }
        }
        _ => compare(&va, &vb, "payload", tol, fields.entry("payload".into()).or_default()),
    }
    Ok(Report { kind: kind_a, fields })
}

fn compare(a: &Value, b: &Value, path: &str, tol: f64, f: &mut FieldDiff) {
    match (a, b) {
        (Value::Array(xs), Value::Array(ys)) => {
            if xs.len() != ys.len() {
                f.counts.push(format!("{path}: {} vs {}", xs.len(), ys.len()));
            }
            for (i, (x, y)) in xs.iter().zip(ys).enumerate() {
                compare(x, y, &format!("{path}[{i}]"), tol, f);
            }
        }
        (Value::Object(xs), Value::Object(ys)) => {
            for (key, x) in xs {
                compare(x, ys.get(key).unwrap_or(&Value::Null), &format!("{path}.{key}"), tol, f);
            }
            for key in ys.keys().filter(|k| !xs.contains_key(*k)) {
                f.compared += 1;
                f.differing += 1;
                f.counts.push(format!("{path}.{key}: missing vs present"));
            }
        }
        (Value::Number(x), Value::Number(y)) => {
            let (x, y) = (x.as_f64().unwrap_or(f64::NAN), y.as_f64().unwrap_or(f64::NAN));
            f.compared += 1;
            let d = (x - y).abs();
            // NaN never compares within tolerance, so it counts as a difference.
            let within = d <= tol * 1f64.max(x.abs()).max(y.abs());
            if !within {
                f.differing += 1;
            }
            if d > 0.0 && f.largest.as_ref().is_none_or(|(best, _)| d > *best) {
                f.largest = Some((d, path.to_string()));
            }
        }
        _ => {
            f.compared += 1;
            if a != b {
                f.differing += 1;
            }
        }
    }
}
