//! The verdict of the calibrated scene: the best candidate's metrics (medians over the seeds)
//! against the target, with the hints a run of the calibrated scene gives (`karst_metrics::hints`,
//! the one source of hints).

use std::collections::BTreeMap;

use karst_metrics::aim;
use karst_metrics::hints::{self, Parameters};
use karst_metrics::ranges::{CHARACTERIZE_KEYS, Compared, real_cave_ranges};
use karst_scene::Scene;

use super::evaluate::MetricVector;
use super::target::Target;

/// `verdict: …` then one `  hint: …` line per metric off the target.
pub fn lines(
    metrics: &MetricVector,
    scene: &Scene,
    derived: &BTreeMap<String, serde_json::Value>,
    target: &Target,
) -> Vec<String> {
    let karstnet = compared(metrics);
    let goal = aim::Target { name: target.name.clone(), statistics: target.metrics };
    let verdict = hints::against(&karstnet, &goal);
    let parameters = Parameters { skeleton: scene.skeleton(), sampling: scene.sampling(), derived };
    let head = format!(
        "verdict of the calibrated scene: {}; {}",
        hints::target_line(&verdict),
        hints::verdict(&karstnet)
    );
    std::iter::once(head)
        .chain(
            hints::target_hints(&karstnet, &verdict, &parameters).into_iter().map(|h| format!("  hint: {h}")),
        )
        .collect()
}

/// Each metric beside its real-cave range, as the metrics stage compares them.
fn compared(metrics: &MetricVector) -> BTreeMap<String, Compared> {
    let ranges = real_cave_ranges();
    CHARACTERIZE_KEYS
        .iter()
        .zip(metrics)
        .map(|(&key, &value)| {
            let range = ranges[key].clone();
            let inside = range.contains(value);
            (key.to_string(), Compared { value, real_caves: range, inside })
        })
        .collect()
}
