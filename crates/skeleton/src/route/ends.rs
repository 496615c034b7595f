//! The ends of routes: the sinks and springs of the scene as the modes route them, the
//! sinks' iteration order and the choice of the springs a sink drains to.
//!
//! Sinks are taken by increasing `order`; sinks of equal order are shuffled by the scene seed
//! (KarstNSim §1.4: "by default, the iteration order ... is randomized"). A sink drains to every
//! spring its connectivity row marks 1; when the row has no 1, to the cheapest of the springs
//! marked 2 (uncertain connectivity keeps the closest spring in the cost metric).

use karst_sampling::Samples;
use karst_scene::rng::Random;
use karst_scene::{KeyPointKind, Link, keypoints_of};

use crate::error::SkeletonError;
use crate::view::SkeletonView;

/// A sink or a spring: its row (column) in the connectivity matrix, its scene key point.
#[derive(Debug, Clone, Copy)]
pub struct End<'a> {
    pub row: usize,
    pub keypoint: usize,
    pub name: &'a str,
}

/// The ends of `kind`, in scene order.
pub fn ends<'s>(view: &SkeletonView<'s>, kind: KeyPointKind) -> Vec<End<'s>> {
    keypoints_of(view.keypoints, kind)
        .enumerate()
        .map(|(row, (keypoint, k))| End { row, keypoint, name: &k.name })
        .collect()
}

/// The sinks by increasing `order`, equal orders shuffled by the seed.
pub fn sinks_in_order<'s>(view: &SkeletonView<'s>) -> Vec<End<'s>> {
    let mut rng = Random::stream(view.seed, "skeleton", "sink order");
    let mut keyed: Vec<(i64, u64, End)> = ends(view, KeyPointKind::Sink)
        .into_iter()
        .map(|s| (view.keypoints[s.keypoint].order, (rng.uniform() * 2f64.powi(53)) as u64, s))
        .collect();
    keyed.sort_by_key(|(order, key, s)| (*order, *key, s.row));
    keyed.into_iter().map(|(_, _, s)| s).collect()
}

/// The springs `sink` drains to among `springs`, given the cost of reaching each allowed spring
/// (infinite when unreachable): every spring marked 1, else the cheapest marked 2; none when
/// no spring of `springs` is allowed. Errors name the sink and the spring it cannot reach.
pub fn chosen_springs<'a>(
    view: &SkeletonView,
    sink: &End,
    springs: &[End<'a>],
    cost_to: &mut dyn FnMut(&End<'a>) -> Result<f64, SkeletonError>,
) -> Result<Vec<End<'a>>, SkeletonError> {
    let allowed = allowed_springs(view, sink, springs);
    let unreachable =
        |t: &End| SkeletonError::SinkCannotReachSpring { sink: sink.name.into(), spring: t.name.into() };
    if allowed.is_empty() {
        return Ok(Vec::new());
    }
    let connected: Vec<End> =
        allowed.iter().filter(|(_, l)| *l == Link::Connected).map(|(t, _)| *t).collect();
    if !connected.is_empty() {
        for t in &connected {
            if !cost_to(t)?.is_finite() {
                return Err(unreachable(t));
            }
        }
        return Ok(connected);
    }
    let mut best: Option<(f64, End)> = None;
    for (t, _) in &allowed {
        let cost = cost_to(t)?;
        if cost.is_finite() && best.is_none_or(|(b, _)| cost < b) {
            best = Some((cost, *t));
        }
    }
    match best {
        Some((_, t)) => Ok(vec![t]),
        None => Err(unreachable(&allowed[0].0)),
    }
}

/// The springs [`chosen_springs`] asks the cost of, in the order it asks: those the sink's
/// connectivity row marks 1, else those it marks 2.
pub fn candidate_springs<'a>(view: &SkeletonView, sink: &End, springs: &[End<'a>]) -> Vec<End<'a>> {
    let allowed = allowed_springs(view, sink, springs);
    let connected: Vec<End> =
        allowed.iter().filter(|(_, l)| *l == Link::Connected).map(|(t, _)| *t).collect();
    if connected.is_empty() { allowed.into_iter().map(|(t, _)| t).collect() } else { connected }
}

/// The springs the sink's connectivity row does not forbid, with their link.
fn allowed_springs<'a>(view: &SkeletonView, sink: &End, springs: &[End<'a>]) -> Vec<(End<'a>, Link)> {
    springs
        .iter()
        .map(|t| (*t, view.connectivity.link(sink.row, t.row)))
        .filter(|(_, l)| *l != Link::None)
        .collect()
}

/// The sample of a key point, or an error naming it.
pub fn sample_of(samples: &Samples, end: &End) -> Result<usize, SkeletonError> {
    samples
        .keypoint_sample(end.keypoint)
        .ok_or_else(|| SkeletonError::KeyPointNotSampled { name: end.name.into() })
}
