//! Running candidates: a candidate is the scene with some network parameters changed; it runs
//! sampling, cost graph and skeleton in memory (no file is written) on each calibration seed,
//! and its network is characterised as the metrics stage does.
//!
//! What the box leaves alone is computed once per seed and shared: without sampling parameters
//! in the box every candidate of a seed has the same samples, and without cost-graph parameters
//! too the same cost graph, so a candidate then costs one skeleton. Items (candidate, seed) run
//! in parallel and are gathered in order, so the results do not depend on the number of
//! threads.

use std::collections::BTreeMap;
use std::sync::Arc;

use rayon::prelude::*;

use karst_costgraph::{CostGraph, CostgraphView};
use karst_metrics::ranges::CHARACTERIZE_KEYS;
use karst_sampling::{Samples, SamplingView};
use karst_scene::{Scene, SceneView, Section};
use karst_skeleton::SkeletonView;

use super::error::CalibrateError;

/// The ten `characterize_graph()` metrics of a network, in karstnet's order.
pub type MetricVector = [f64; CHARACTERIZE_KEYS.len()];

/// The seeds and what they share.
pub struct Runner {
    seeds: Vec<u64>,
    shared: Vec<Upstream>,
}

/// What a seed's candidates share.
#[derive(Default)]
struct Upstream {
    samples: Option<Arc<Samples>>,
    graph: Option<Arc<CostGraph>>,
}

impl Runner {
    /// Prepares the `seeds` of `scene`, sharing the stages none of the `sections` (those the
    /// box changes) feeds: a stage is shared when its view holds none of them, nor does any
    /// stage's before it.
    pub fn new(scene: &Scene, seeds: Vec<u64>, sections: &[Section]) -> Result<Runner, CalibrateError> {
        let reads = |view: &[Section]| sections.iter().any(|s| view.contains(s));
        let shares_samples = !reads(SamplingView::SECTIONS);
        let shares_graph = shares_samples && !reads(CostgraphView::SECTIONS);
        let shared = seeds
            .par_iter()
            .map(|&seed| {
                let scene = with_seed(scene, seed);
                let mut upstream = Upstream::default();
                if shares_samples {
                    let samples = Arc::new(
                        karst_sampling::build(&SamplingView::of(&scene))
                            .map_err(|e| CalibrateError::stage("sampling", e))?,
                    );
                    if shares_graph {
                        let graph = karst_costgraph::build(&CostgraphView::of(&scene), &samples)
                            .map_err(|e| CalibrateError::stage("costgraph", e))?;
                        upstream.graph = Some(Arc::new(graph));
                    }
                    upstream.samples = Some(samples);
                }
                Ok(upstream)
            })
            .collect::<Result<Vec<_>, CalibrateError>>()?;
        Ok(Runner { seeds, shared })
    }

    /// The seeds, in order.
    pub fn seeds(&self) -> &[u64] {
        &self.seeds
    }

    /// The metrics of every candidate on every seed (`[candidate][seed]`), or why a run failed;
    /// `done` is called after each run.
    pub fn run(
        &self,
        candidates: &[Scene],
        done: &(dyn Fn() + Sync),
    ) -> Vec<Vec<Result<MetricVector, CalibrateError>>> {
        let items: Vec<(usize, usize)> =
            (0..candidates.len()).flat_map(|c| (0..self.seeds.len()).map(move |s| (c, s))).collect();
        let results: Vec<Result<MetricVector, CalibrateError>> = items
            .par_iter()
            .map(|&(c, s)| {
                let r = self.network_metrics(&with_seed(&candidates[c], self.seeds[s]), &self.shared[s]);
                done();
                r
            })
            .collect();
        let mut results = results.into_iter();
        (0..candidates.len()).map(|_| results.by_ref().take(self.seeds.len()).collect()).collect()
    }

    /// The defaults the skeleton derives for `scene` on the first seed (what the hints cite).
    pub fn derived(&self, scene: &Scene) -> Result<BTreeMap<String, serde_json::Value>, CalibrateError> {
        let scene = with_seed(scene, self.seeds[0]);
        Ok(self.skeleton(&scene, &self.shared[0])?.derived)
    }

    fn network_metrics(&self, scene: &Scene, upstream: &Upstream) -> Result<MetricVector, CalibrateError> {
        let skeleton = self.skeleton(scene, upstream)?;
        let metrics = karst_metrics::characterize(&karst_metrics::network_of(&skeleton))
            .map_err(|e| CalibrateError::stage("metrics", e))?;
        Ok(metric_vector(&metrics))
    }

    fn skeleton(
        &self,
        scene: &Scene,
        upstream: &Upstream,
    ) -> Result<karst_skeleton::Skeleton, CalibrateError> {
        let samples = match &upstream.samples {
            Some(samples) => Arc::clone(samples),
            None => Arc::new(
                karst_sampling::build(&SamplingView::of(scene))
                    .map_err(|e| CalibrateError::stage("sampling", e))?,
            ),
        };
        let graph = match &upstream.graph {
            Some(graph) => Arc::clone(graph),
            None => Arc::new(
                karst_costgraph::build(&CostgraphView::of(scene), &samples)
                    .map_err(|e| CalibrateError::stage("costgraph", e))?,
            ),
        };
        karst_skeleton::build(&SkeletonView::of(scene), &samples, &graph)
            .map_err(|e| CalibrateError::stage("skeleton", e))
    }
}

/// The `characterize_graph()` metrics of `metrics`, in karstnet's order.
pub fn metric_vector(metrics: &karst_metrics::Metrics) -> MetricVector {
    karst_metrics::aim::statistics_of(metrics)
}

fn with_seed(scene: &Scene, seed: u64) -> Scene {
    let mut scene = scene.clone();
    scene.set_seed(seed);
    scene
}
