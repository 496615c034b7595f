//! The verdict that closes `karstgen run`: how many of karstnet's ten metrics lie in the
//! real-cave ranges and, for each outside, the hint the metrics stage wrote into `metrics.json`
//! (`karst_metrics::hints`, the one source of hints). It is read back from `metrics.json` so
//! that a run whose metrics were up to date ends with it too.

use std::path::Path;

use karst_artifact::{StageId, read_artifact};
use karst_metrics::{MetricsReport, hints};
use karst_stage::StageError;

use crate::make::{Outcome, StageReport};

/// The verdict's lines when the run reached the metrics stage (ran or up to date), else none.
pub fn verdict(out: &Path, reports: &[StageReport]) -> Result<Vec<String>, StageError> {
    let reached = reports.iter().any(|r| r.stage == StageId::Metrics && r.outcome != Outcome::Skipped);
    if !reached {
        return Ok(Vec::new());
    }
    let path = out.join(StageId::Metrics.file_name());
    let (_, report) = read_artifact::<MetricsReport>(&path)
        .map_err(|e| StageError::failure(format!("{}: {e}", path.display())))?;
    Ok(lines(&report))
}

/// `verdict: N/10 inside real-cave ranges` (preceded by `M/10 on target (NAME), distance D; `
/// when the scene names a calibration target), then one `hint:` line per metric outside the
/// ranges, or off the target.
fn lines(report: &MetricsReport) -> Vec<String> {
    let head = format!("verdict: {}", hints::verdict_of(report));
    std::iter::once(head).chain(report.hints.iter().map(|h| format!("  hint: {h}"))).collect()
}
