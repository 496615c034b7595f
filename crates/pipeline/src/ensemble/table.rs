//! The summary table of an ensemble: one row per complete realization (by seed), one column
//! per figure, and its statistics.
//!
//! Columns: `seed`; every statistic of `metrics.json` under karstnet's key names; `vadose
//! length` and `phreatic length`; `<type> length` per conduit type; when hydro ran, `<type>
//! water length` per water type and `<spring> discharge (m3/s)` per spring (every spring any
//! realization reports, by name; empty where a realization's water does not reach it).
//! Undefined values (NaN, and the infinite Howard γ of a two-node graph) are NaN in the table
//! and empty cells in CSV, as records keep them (JSON `null`).

use std::collections::BTreeSet;
use std::fmt::Write as _;

use karst_metrics::ranges::{CHARACTERIZE_KEYS, real_cave_ranges};

use super::record::Figures;

/// Column names and one row of values per realization.
#[derive(Debug, Clone, PartialEq)]
pub struct Table {
    pub columns: Vec<String>,
    pub rows: Vec<Vec<f64>>,
}

/// The table of the realizations `(seed, figures)`, in the order given.
pub fn table(realizations: &[(u64, &Figures)]) -> Table {
    let Some((_, first)) = realizations.first() else {
        return Table { columns: vec!["seed".into()], rows: Vec::new() };
    };
    let springs: BTreeSet<&str> =
        realizations.iter().flat_map(|(_, f)| f.springs.iter().map(|s| s.name.as_str())).collect();
    let mut columns = vec!["seed".to_string()];
    columns.extend(first.report.network.to_pairs().into_iter().map(|(k, _)| k.to_string()));
    columns.extend(["vadose length".to_string(), "phreatic length".to_string()]);
    columns.extend(first.report.conduit_types.keys().map(|t| format!("{t} length")));
    columns.extend(first.report.water_types.keys().map(|t| format!("{t} water length")));
    columns.extend(springs.iter().map(|s| format!("{s} discharge (m3/s)")));
    let rows = realizations
        .iter()
        .map(|(seed, f)| {
            let r = &f.report;
            let mut row = vec![*seed as f64];
            row.extend(r.network.to_pairs().into_iter().map(|(_, v)| v));
            row.extend([r.zones.vadose, r.zones.phreatic]);
            row.extend(r.conduit_types.values().copied());
            row.extend(
                first.report.water_types.keys().map(|t| r.water_types.get(t).copied().unwrap_or(f64::NAN)),
            );
            row.extend(
                springs
                    .iter()
                    .map(|name| f.springs.iter().find(|s| s.name == *name).map_or(f64::NAN, |s| s.discharge)),
            );
            row.iter_mut().filter(|v| !v.is_finite()).for_each(|v| *v = f64::NAN);
            row
        })
        .collect();
    Table { columns, rows }
}

/// `metrics.csv`: the header, then one line per realization.
pub fn csv(table: &Table) -> String {
    let mut out = quoted(&table.columns).join(",") + "\n";
    for row in &table.rows {
        let cells: Vec<String> = row.iter().map(|&v| show(v)).collect();
        out += &(cells.join(",") + "\n");
    }
    out
}

fn quoted(names: &[String]) -> Vec<String> {
    names.iter().map(|n| quote(n)).collect()
}

fn quote(text: &str) -> String {
    format!("\"{}\"", text.replace('"', "\"\""))
}

fn show(v: f64) -> String {
    if v.is_finite() { v.to_string() } else { String::new() }
}

/// `summary.csv`: min, mean, max and the number of defined values per column (seed excluded)
/// and, for karstnet's metrics, the real-cave range and the fraction of realizations inside it.
pub fn summary(table: &Table) -> String {
    let ranges = real_cave_ranges();
    let mut out = String::from("metric,min,mean,max,defined,real_caves_min,real_caves_max,fraction_inside\n");
    for (c, name) in table.columns.iter().enumerate().skip(1) {
        let values: Vec<f64> = table.rows.iter().map(|r| r[c]).filter(|v| v.is_finite()).collect();
        let (min, max) =
            values.iter().fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), &v| (a.min(v), b.max(v)));
        let mean = values.iter().sum::<f64>() / values.len() as f64;
        let _ = write!(out, "{},{},{},{},{}", quote(name), show(min), show(mean), show(max), values.len());
        match CHARACTERIZE_KEYS.contains(&name.as_str()).then(|| &ranges[name]) {
            Some(r) => {
                let inside = table.rows.iter().filter(|row| r.contains(row[c])).count();
                let _ = writeln!(out, ",{},{},{}", r.min, r.max, inside as f64 / table.rows.len() as f64);
            }
            None => out.push_str(",,,\n"),
        }
    }
    out
}

/// `failures.csv`: the seed and the error of every failed realization.
pub fn failures_csv(failures: &[(u64, String)]) -> String {
    let mut out = String::from("seed,error\n");
    for (seed, error) in failures {
        let _ = writeln!(out, "{seed},{}", quote(error));
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn summary_skips_undefined_values_and_counts_inside() {
        let table = Table {
            columns: vec!["seed".into(), "tortuosity".into(), "n_branches".into()],
            rows: vec![vec![1.0, 1.2, 3.0], vec![2.0, f64::NAN, 5.0], vec![3.0, 2.0, 4.0]],
        };
        let s = summary(&table);
        let lines: Vec<&str> = s.lines().collect();
        assert!(lines[1].starts_with("\"tortuosity\",1.2,1.6,2,2,"), "{}", lines[1]);
        assert!(lines[1].ends_with(&format!(",{}", 1.0 / 3.0)), "{}", lines[1]);
        assert_eq!(lines[2], "\"n_branches\",3,4,5,3,,,");
        assert_eq!(csv(&table).lines().nth(2), Some("2,,5"));
    }

    #[test]
    fn failures_quote_their_messages() {
        assert_eq!(failures_csv(&[(7, "a \"b\", c".into())]), "seed,error\n7,\"a \"\"b\"\", c\"\n");
    }
}
