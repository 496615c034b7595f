//! `cargo xtask ensemble [--n 20] [--write]`: the robustness of the presets. Every preset runs
//! `karstgen ensemble` (seeds scene seed + 0 … n − 1) and its karstnet metrics are tabled
//! against the real-cave ranges: per preset and metric the median, the 10th–90th percentile and
//! the share of realizations inside the range, then the share inside all ten ranges.
//!
//! With `--write` the table replaces docs/metrics.md's section between
//! `<!-- ensemble-table -->` and `<!-- /ensemble-table -->`, so that it is regenerated, never
//! edited by hand.

use std::fmt::Write as _;
use std::path::PathBuf;

use karst_artifact::StageId;
use karst_metrics::ranges::{CHARACTERIZE_KEYS, real_cave_ranges};
use karst_pipeline::ensemble::{self, Keep, Plan};
use karst_pipeline::scene::SceneFile;
use karst_plot::bins::quantile;
use karst_stage::StageError;

pub const BEGIN: &str = "<!-- ensemble-table -->";
pub const END: &str = "<!-- /ensemble-table -->";

/// The presets whose realizations must pass for real caves (issue 20); `tiny` and `layered`
/// are test scenes, exempt (docs/metrics.md).
pub const PRESETS: [&str; 7] =
    ["default", "branchwork", "looping", "rectilinear", "superimposed", "karstnsim", "karstnsim-2phase"];

/// One preset's realizations: every column of the ensemble's `metrics.csv` by name.
pub struct Realizations {
    pub preset: String,
    pub columns: Vec<String>,
    pub rows: Vec<Vec<f64>>,
}

impl Realizations {
    /// The values of column `name` (NaN where undefined).
    fn column(&self, name: &str) -> Vec<f64> {
        let c = self.columns.iter().position(|n| n == name).expect("ensemble writes every karstnet metric");
        self.rows.iter().map(|r| r[c]).collect()
    }

    /// Fraction of realizations inside the range of every karstnet metric.
    fn all_inside(&self) -> f64 {
        let ranges = real_cave_ranges();
        let inside = (0..self.rows.len())
            .filter(|&i| CHARACTERIZE_KEYS.iter().all(|k| ranges[*k].contains(self.column(k)[i])))
            .count();
        inside as f64 / self.rows.len() as f64
    }
}

/// Runs `n` realizations of `fixtures/scenes/<preset>.toml` to the skeleton in
/// `out/ensemble-table/<preset>` (emptied first: the presets change between runs) and returns
/// their metrics; a failed realization is an error.
pub fn realize(preset: &str, n: usize) -> Result<Realizations, StageError> {
    let out = PathBuf::from("out/ensemble-table").join(preset);
    let _ = std::fs::remove_dir_all(&out);
    let scene = SceneFile::load(&PathBuf::from("fixtures/scenes").join(format!("{preset}.toml")))?;
    let seeds =
        ensemble::first_n(scene.scene.seed(), n).map_err(|e| StageError::input(format!("ensemble: {e}")))?;
    let plan = Plan::new(scene, Some(StageId::Skeleton), ensemble::DEFAULT_CELL, Keep::Stages(Vec::new()))?;
    let summary = ensemble::run(&plan, &out, &seeds, None)?;
    if let Some((seed, error)) = summary.failures.first() {
        return Err(StageError::failure(format!("{preset}: seed {seed}: {error}")));
    }
    Ok(Realizations { preset: preset.to_string(), columns: summary.table.columns, rows: summary.table.rows })
}

/// The Markdown table: one row per metric, one column per preset.
pub fn markdown(sets: &[Realizations]) -> String {
    let ranges = real_cave_ranges();
    let n = sets.first().map_or(0, |s| s.rows.len());
    let mut out = format!(
        "{n} seeds per preset: median (10th–90th percentile) and share inside the real-cave range.\n\n| metric |"
    );
    for s in sets {
        let _ = write!(out, " {} |", s.preset);
    }
    out += " real caves |\n|---|";
    out += &"---|".repeat(sets.len());
    out += "---|\n";
    for key in CHARACTERIZE_KEYS {
        let _ = write!(out, "| {key} |");
        for s in sets {
            let values = s.column(key);
            let inside = values.iter().filter(|v| ranges[key].contains(**v)).count();
            let _ =
                write!(out, " {} {:.0} % |", spread(&values), 100.0 * inside as f64 / values.len() as f64);
        }
        let _ = writeln!(out, " {} – {} |", short(ranges[key].min), short(ranges[key].max));
    }
    out += "| total length (m) |";
    for s in sets {
        let _ = write!(out, " {} |", spread(&s.column("total_length")));
    }
    out += " |\n| **inside all ten** |";
    for s in sets {
        let _ = write!(out, " **{:.0} %** |", 100.0 * s.all_inside());
    }
    out += " |\n";
    out
}

/// "median (p10–p90)" of the defined values.
fn spread(values: &[f64]) -> String {
    let mut v: Vec<f64> = values.iter().copied().filter(|v| v.is_finite()).collect();
    if v.is_empty() {
        return "undefined".into();
    }
    v.sort_by(f64::total_cmp);
    format!("{} ({}–{})", short(quantile(&v, 0.5)), short(quantile(&v, 0.1)), short(quantile(&v, 0.9)))
}

/// Three significant digits.
fn short(v: f64) -> String {
    let digits = if v.abs() >= 100.0 {
        0
    } else if v.abs() >= 10.0 {
        1
    } else {
        3 - usize::from(v.abs() >= 1.0)
    };
    format!("{v:.digits$}")
}

#[cfg(test)]
mod tests {
    use super::*;

    fn set(rows: Vec<Vec<f64>>) -> Realizations {
        let mut columns = vec!["seed".to_string()];
        columns.extend(CHARACTERIZE_KEYS.iter().map(|k| k.to_string()));
        columns.push("total_length".into());
        Realizations { preset: "p".into(), columns, rows }
    }

    #[test]
    fn shares_count_realizations_inside_every_range() {
        // Inside every range, then one with an assortative network (correlation +0.1).
        let good = vec![0.0, 50.0, 1.2, 0.4, 1.2, 0.9, 5.0, 0.3, 2.1, 0.45, -0.3, 1000.0];
        let mut bad = good.clone();
        bad[10] = 0.1;
        let s = set(vec![good.clone(), good, bad]);
        assert!((s.all_inside() - 2.0 / 3.0).abs() < 1e-12);
        let table = markdown(&[s]);
        assert!(table.contains("| correlation vertex degree | -0.300 (-0.300–0.020) 67 % |"), "{table}");
        assert!(table.contains("| **inside all ten** | **67 %** |"), "{table}");
    }

    #[test]
    fn short_keeps_three_significant_digits() {
        assert_eq!(short(1234.5), "1234");
        assert_eq!(short(55.72), "55.7");
        assert_eq!(short(2.3214), "2.32");
        assert_eq!(short(0.0224), "0.022");
    }
}
