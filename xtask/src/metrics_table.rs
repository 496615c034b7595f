//! `cargo xtask metrics-table [--write]`: every scene of `fixtures/scenes/` (each `*.toml`) run
//! through sampling, costgraph, skeleton and metrics, and karstnet's metrics of all of them
//! tabled in Markdown against the ranges of the real caves (Collon et al. 2017).
//!
//! With `--write`, each scene's `metrics.json` is copied to `fixtures/metrics/<scene>.json` and
//! the table replaces the README's section between `<!-- metrics-table -->` and
//! `<!-- /metrics-table -->`, so that both can be regenerated after presets change.

use std::fmt::Write as _;
use std::path::{Path, PathBuf};

use karst_artifact::{StageId, read_artifact};
use karst_metrics::MetricsReport;
use karst_metrics::ranges::{CHARACTERIZE_KEYS, real_cave_ranges};
use karst_pipeline::registry;
use karst_pipeline::scene::SceneFile;
use karst_stage::{Job, StageError};

const BEGIN: &str = "<!-- metrics-table -->";
const END: &str = "<!-- /metrics-table -->";

/// The scenes of `dir`, sorted by file name.
pub fn scenes(dir: &Path) -> Result<Vec<PathBuf>, StageError> {
    let entries =
        std::fs::read_dir(dir).map_err(|e| StageError::failure(format!("{}: {e}", dir.display())))?;
    let mut scenes: Vec<PathBuf> = entries
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| p.extension().is_some_and(|e| e == "toml"))
        .collect();
    scenes.sort();
    Ok(scenes)
}

/// Runs the stages up to metrics for `scene` into `out` and reads its report.
pub fn scene_report(scene: &Path, out: &Path) -> Result<MetricsReport, StageError> {
    let loaded = SceneFile::load(scene)?;
    let job = Job::new(scene, &loaded.scene, out);
    let stages = [
        StageId::Sampling,
        StageId::Costgraph,
        StageId::Skeleton,
        StageId::Hydro,
        StageId::Streams,
        StageId::Sdf,
        StageId::Survey,
        StageId::Metrics,
    ];
    for stage in stages {
        registry::stage(stage).run(&job)?;
    }
    Ok(read_artifact::<MetricsReport>(&job.artifact(StageId::Metrics))?.1)
}

/// The Markdown table: one row per karstnet metric, one column per scene, then the range.
pub fn markdown(reports: &[(String, MetricsReport)]) -> String {
    let ranges = real_cave_ranges();
    let mut out = String::from("| metric |");
    for (name, _) in reports {
        let _ = write!(out, " {name} |");
    }
    out += " real caves (min – max) |\n|---|";
    out += &"---:|".repeat(reports.len());
    out += "---|\n";
    for key in CHARACTERIZE_KEYS {
        let _ = write!(out, "| {key} |");
        for (_, report) in reports {
            let c = &report.karstnet[key];
            let value = if c.value.is_finite() { format!("{:.3}", c.value) } else { "undefined".into() };
            let _ = write!(out, " {} |", if c.inside { value } else { format!("**{value}** ✗") });
        }
        let r = &ranges[key];
        let _ = writeln!(out, " {:.3} – {:.3} |", r.min, r.max);
    }
    for (label, count) in [
        (
            "nodes / branches",
            (|r: &MetricsReport| format!("{} / {}", r.network.n_nodes_full, r.network.n_branches))
                as fn(&MetricsReport) -> String,
        ),
        ("cycles", |r| r.network.n_cycles.to_string()),
        ("total length (m)", |r| format!("{:.0}", r.network.total_length)),
        ("inside the ranges", |r| format!("{}/10", r.karstnet.values().filter(|c| c.inside).count())),
    ] {
        let _ = write!(out, "| {label} |");
        for (_, report) in reports {
            let _ = write!(out, " {} |", count(report));
        }
        out += " |\n";
    }
    out
}

/// Replaces the README section between the markers (appending it when missing).
pub fn replace_section(readme: &str, table: &str) -> String {
    replace_between(readme, BEGIN, END, table)
}

/// Replaces the section of `text` between the markers `begin` and `end` (appending it when
/// missing).
pub fn replace_between(text: &str, begin: &str, end: &str, table: &str) -> String {
    let block = format!("{begin}\n{table}{end}");
    match (text.find(begin), text.find(end)) {
        (Some(a), Some(b)) if a < b => format!("{}{block}{}", &text[..a], &text[b + end.len()..]),
        _ => format!("{text}\n{block}\n"),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn section_is_replaced_between_the_markers() {
        let readme = format!("intro\n{BEGIN}\nold\n{END}\noutro\n");
        assert_eq!(replace_section(&readme, "new\n"), format!("intro\n{BEGIN}\nnew\n{END}\noutro\n"));
        assert_eq!(replace_section("a\n", "t\n"), format!("a\n\n{BEGIN}\nt\n{END}\n"));
    }
}
