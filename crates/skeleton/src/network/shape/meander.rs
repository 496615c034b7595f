//! Meanders: conduits bend in the bedding plane, as cave streams do.
//!
//! Solution conduits are sinuous like surface channels: vadose canyons meander as their stream
//! swings from wall to wall and cuts down, and phreatic tubes wind along the bedding parting
//! they formed on; Deike & White (1969, "Sinuosity in limestone solution conduits") found cave
//! meanders scaled like those of rivers. The least-cost paths of the cost graph are straight
//! at every scale above the sampling radius, so on their own they give branch tortuosities of
//! 1.05–1.09, below every real cave of Collon et al. 2017 (1.12–1.54). Paris et al.'s
//! midpoint displacement (θ ≤ 4 m per sample link) is roughness, not sinuosity.
//!
//! Each conduit that is not a shaft (chord steeper than `skeleton.vertical_angle`) and not a
//! closed loop is bent by a sine-generated offset in its bedding plane: the plane of the
//! nearest inception horizon (horizontal when the scene has none), across the conduit's chord.
//! The conduit draws a wavelength in `skeleton.meander_wavelength` and fits a whole number of
//! half-waves between its ends, which stay in place (junctions, key points); the amplitude is
//! the one whose sine has the sinuosity `skeleton.sinuosity` (arc length over chord of
//! y = a·sin(kx): (1/2π)∫₀^2π √(1 + (ak)² cos² t) dt). Points are inserted where the
//! conduit's nodes are farther apart than a sixth of the wavelength; an offset that would leave
//! the bedrock is halved until it does not. The side of the first bend is drawn per conduit.

use std::f64::consts::{PI, TAU};

use glam::DVec3;
use karst_scene::rng::Random;

use crate::network::nodes::node_at;
use crate::network::shape::planes::WeaknessPlanes;
use crate::network::shape::tortuosity::Insertions;
use crate::payload::Node;
use crate::view::SkeletonView;

/// Halvings of an offset that leaves the bedrock before the point stays on the chord.
const TRIES: usize = 6;

/// The sine's a·k for a sinuosity σ ≥ 1 (bisection on the monotone arc-length integral).
pub fn amplitude_ratio(sinuosity: f64) -> f64 {
    let (mut lo, mut hi) = (0.0, 20.0);
    for _ in 0..60 {
        let mid = 0.5 * (lo + hi);
        if sine_sinuosity(mid) < sinuosity {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    0.5 * (lo + hi)
}

/// Arc length over chord of y = a·sin(x/k·…) with a·k = `ak`, by Simpson's rule.
fn sine_sinuosity(ak: f64) -> f64 {
    let n = 256;
    let f = |t: f64| (1.0 + (ak * t.cos()).powi(2)).sqrt();
    let h = TAU / n as f64;
    let sum: f64 = (0..=n)
        .map(|i| {
            f(i as f64 * h)
                * if i == 0 || i == n {
                    1.0
                } else if i % 2 == 1 {
                    4.0
                } else {
                    2.0
                }
        })
        .sum();
    sum * h / 3.0 / TAU
}

/// Bends every conduit of `chains` in place; returns the nodes inserted into each link.
pub fn bend(
    view: &SkeletonView,
    sinuosity: f64,
    nodes: &mut Vec<Node>,
    chains: &mut [Vec<u32>],
) -> Insertions {
    let p = view.skeleton;
    let ak = amplitude_ratio(sinuosity);
    let mut rng = Random::stream(view.seed, "skeleton", "meanders");
    let planes = WeaknessPlanes::of(&karst_costgraph::fracture_families(&view.costs()));
    let mut inserted = Insertions::new();
    for chain in chains.iter_mut() {
        let [shortest, longest] = p.meander_wavelength.unwrap_or_default();
        let wavelength = rng.range(shortest, longest);
        let originals: Vec<DVec3> =
            chain.iter().map(|&i| DVec3::from_array(nodes[i as usize].position)).collect();
        let chord = originals[originals.len() - 1] - originals[0];
        let dip =
            if chord == DVec3::ZERO { 90.0 } else { (chord.z.abs() / chord.length()).asin().to_degrees() };
        let length: f64 = originals.windows(2).map(|w| w[0].distance(w[1])).sum();
        let meander = Meander::draw(&mut rng, length, wavelength, ak);
        if chain[0] == chain[chain.len() - 1] || dip >= p.vertical_angle {
            continue;
        }
        let across =
            planes.across(view.geology, (originals[0] + originals[originals.len() - 1]) * 0.5, chord);
        *chain = meander.apply(view, &across, &originals, chain, nodes, &mut inserted);
    }
    inserted
}

/// The offset of one conduit: a whole number of half-waves of a sine along its length, each
/// with its own amplitude (cave meanders are not regular), alternately to either side.
struct Meander {
    length: f64,
    /// Signed amplitude of each half-wave, metres.
    amplitudes: Vec<f64>,
}

impl Meander {
    /// Half-waves of about `wavelength` / 2 over `length`, amplitudes 0.5–1.5 times the one of
    /// the sine of a·k = `ak`, the first to a random side.
    fn draw(rng: &mut Random, length: f64, wavelength: f64, ak: f64) -> Self {
        let half_waves = (2.0 * length / wavelength).round().max(1.0) as usize;
        let local = 2.0 * length / half_waves as f64;
        let side = if rng.uniform() < 0.5 { -1.0 } else { 1.0 };
        let amplitudes = (0..half_waves).map(|_| side * rng.range(0.5, 1.5) * ak * local / TAU).collect();
        Meander { length, amplitudes }
    }

    /// The offset at arc length `s` (zero at both ends and between half-waves).
    fn offset(&self, s: f64) -> f64 {
        let n = self.amplitudes.len() as f64;
        let phase = (s / self.length).clamp(0.0, 1.0) * n;
        let k = (phase as usize).min(self.amplitudes.len() - 1);
        self.amplitudes[k] * (PI * phase).sin()
    }

    /// The conduit `chain` (positions `originals`) moved by the offsets along `across`, with
    /// points inserted a twelfth of a wavelength apart; returns the new chain.
    fn apply(
        &self,
        view: &SkeletonView,
        across: &DVec3,
        originals: &[DVec3],
        chain: &[u32],
        nodes: &mut Vec<Node>,
        inserted: &mut Insertions,
    ) -> Vec<u32> {
        let spacing = self.length / self.amplitudes.len() as f64 / 6.0;
        let mut refined = vec![chain[0]];
        let mut s = 0.0;
        for (k, w) in chain.windows(2).enumerate() {
            let (a, b) = (w[0], w[1]);
            let (pa, pb) = (originals[k], originals[k + 1]);
            let step = pa.distance(pb);
            let pieces = (step / spacing).ceil().max(1.0) as usize;
            let ids: Vec<u32> = (1..pieces)
                .map(|j| {
                    let t = j as f64 / pieces as f64;
                    let q = displaced(view, pa.lerp(pb, t), *across, self.offset(s + step * t));
                    let sample = nodes[if t < 0.5 { a } else { b } as usize].sample;
                    nodes.push(node_at(view.geology, q.to_array(), sample, None));
                    (nodes.len() - 1) as u32
                })
                .collect();
            s += step;
            if k + 2 < chain.len() {
                let q = displaced(view, pb, *across, self.offset(s));
                nodes[b as usize] = node_at(view.geology, q.to_array(), nodes[b as usize].sample, None);
            }
            refined.extend(&ids);
            refined.push(b);
            let forward = if a < b { ids } else { ids.into_iter().rev().collect() };
            inserted.insert((a.min(b), a.max(b)), forward);
        }
        refined
    }
}

/// `p` moved by `offset` along `across`, halved until it lies in the bedrock.
fn displaced(view: &SkeletonView, p: DVec3, across: DVec3, offset: f64) -> DVec3 {
    (0..TRIES).map(|k| p + across * offset / f64::from(1u32 << k)).find(|q| view.in_bedrock(*q)).unwrap_or(p)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_amplitude_gives_the_requested_sinuosity() {
        for sinuosity in [1.0, 1.05, 1.2, 2.0] {
            assert!((sine_sinuosity(amplitude_ratio(sinuosity)) - sinuosity).abs() < 1e-9, "{sinuosity}");
        }
    }
}
