//! Passage profiles: how the size and shape of a passage vary along its conduit, as surveyed
//! caves show them (`[sdf] passage_detail`, docs/skeleton.md "Passages").
//!
//! The radius process ([`crate::ConduitRadii`]) sets a conduit's size over hundreds of metres.
//! Surveyed passages change much faster: from one survey station to the next (3–5 m) their
//! width and height change by a factor of two or three, they pinch to crawls and open into
//! rooms, and they are much wider than high (bedding-plane passages) or much higher than wide
//! (canyons). Across 17 caves of KNdata-public (ERC-Karst 2024) the standard deviation of ln
//! width is 0.72–1.31 and of ln height 0.78–1.07, and the correlation of ln width between
//! adjacent stations only 0.24–0.79 (`fixtures/passages/passage-ranges.json`).
//!
//! Each conduit gets a profile point at every node and every [`SPACING`] metres between them.
//! At each point two standard normal processes, each an order-1 autoregression along the arc
//! length with correlation exp(−Δs / [`CORRELATION`]) (the exponential covariance, sampled
//! exactly as in `radii.rs`), give
//!
//! - the size: ln of the passage's linear size is [`SIZE_SPREAD`] · h(z_size) about the
//!   radius process's value, where h(z) = z·exp(τz²/2) / sd is Tukey's heavy-tailed transform
//!   (τ = [`TAIL`]): dissolution concentrates where the rock is weakest (fractures, beds,
//!   intersections) and breakdown enlarges rooms, so sizes are log-normal with more pinches and
//!   rooms than a normal law gives;
//! - the shape: ln(height / width) is [`SHAPE_SPREAD`] · h(z_shape) plus a bias per conduit type,
//!   on top of the type's own section (canyons and keyholes tall, beds wide): the same passage
//!   alternates between a slot where the stream has incised and a low bedding-plane opening
//!   where it followed a bed. The width takes −½ and the height +½ of that, so the shape does
//!   not change the area.
//!
//! The size is multiplied by two factors that follow from where water goes:
//!
//! - flow: conduits grow with the discharge they carry (hydraulic geometry: a channel's width
//!   grows as a power of its discharge); the share s of the routes' total weight through the
//!   conduit gives 0.6 + 0.5·√s, from dry tributaries (0.6) to the trunk (1.1), divided by the
//!   length-weighted root mean square of these over the network ([`flow_factors`]): flow moves
//!   size from the tributaries to the trunk, it does not shrink a cave of many tributaries (a
//!   maze) below the size the radius process gives it;
//! - junctions: where passages meet, mixing corrosion and the breakdown of the roof over the
//!   wider span enlarge them: 1 + [`JUNCTION_WIDENING`]·exp(−d / r) within a few radii r of a
//!   junction, d the distance along the conduit.
//!
//! Each point's half-width and half-height are then capped at [`ROOM`] times the conduit's size
//! there, and their change along the passage is limited to [`SLOPE`] metres per metre
//! ([`limit_slopes`]): a room opens and a pinch closes over metres.
//!
//! The size factor is divided by the root mean square of exp(σ h(z)) so that the mean
//! cross-section area of the drawn sizes, and with it the void volume and the flow capacity the
//! radius process stands for, stays that of the radius process (the room cap and the slope
//! limit then take some of it out of the largest rooms) (keeping the mean linear size instead would
//! inflate the mean area by E[exp(2σh)] / E[exp(σh)]², about half as much again). The profile is deterministic from the seed: one random stream, conduits in order.

use std::collections::HashMap;

use glam::DVec3;
use karst_scene::rng::Random;

use crate::payload::{ConduitType, Node, ProfilePoint, Route};

/// Largest distance between profile points, metres: finer than a survey's stations (4 m), so
/// that the size changes between any two of them.
pub const SPACING: f64 = 2.0;
/// Correlation length of size and shape along a passage, metres: exp(−4 / 5.5) ≈ 0.48 between
/// stations 4 m apart, the middle of the surveyed caves' 0.24–0.79.
pub const CORRELATION: f64 = 5.5;
/// Standard deviation of the ln of the passage's linear size.
pub const SIZE_SPREAD: f64 = 0.75;
/// Standard deviation of ln(height / width), before the bias of the conduit type.
pub const SHAPE_SPREAD: f64 = 0.9;
/// Tukey's h of the heavy-tailed transform.
pub const TAIL: f64 = 0.1;
/// The normal values are clamped to ±this before the transform: the largest rooms and the
/// tightest pinches are those of one point in several thousand, not unbounded.
pub const Z_MAX: f64 = 3.5;
/// How much wider a passage is at a junction (a fraction of its size).
pub const JUNCTION_WIDENING: f64 = 0.6;
/// Smallest half-width, metres: a squeeze a caver still passes sideways.
pub const MIN_HALF_WIDTH: f64 = 0.5;
/// Smallest half-height, metres: a bedding-plane crawl half a metre high, as surveys record
/// them. The mesher keeps any passage open whatever its size: it meshes the conduits thinner
/// than its cave cell one cell thick.
pub const MIN_HALF_HEIGHT: f64 = 0.25;
/// Fastest change of the half-width and of the half-height along a passage, metres per metre: a
/// wall opens or closes at up to 45° to the passage. Rooms open and pinches close over metres,
/// not within one profile spacing (breakdown and dissolution widen a passage gradually); at
/// this slope a passage up to 4 m wide can still triple between survey stations 4 m apart, as
/// surveyed passages do, and larger ones change more slowly in proportion. It also bounds how
/// fast the swept section moves, and with it the sweep's Lipschitz factor 1/√(1 + k²)
/// (docs/sdf.md "Passage detail").
pub const SLOPE: f64 = 1.0;
/// Largest half-width or half-height of a room, as a multiple of the conduit's size there (the
/// radius process's value times the flow and junction factors): the tail of the size process
/// reaches factors of several tens, but a room is an enlargement of its passage by breakdown
/// and dissolution of the walls, a few times its span, not tens.
pub const ROOM: f64 = 6.0;
/// Range of the shape factor height / width on the type's own proportions.
pub const RATIO_LIMITS: [f64; 2] = [0.08, 12.0];

/// The bias of ln(height / width) per conduit type: bedding-plane (phreatic) conduits spread
/// along their bed, inclined passages follow the dip of beds and joints (both wider still than
/// their sections); vadose canyons and keyholes are already tall in their own sections.
fn shape_bias(kind: ConduitType) -> f64 {
    match kind {
        ConduitType::Bed => -0.5,
        ConduitType::Passage => -0.3,
        ConduitType::Canyon | ConduitType::Keyhole => -0.15,
        ConduitType::Tube | ConduitType::Epikarst | ConduitType::Chamber => 0.0,
    }
}

/// The two processes' values at one point.
#[derive(Debug, Clone, Copy)]
struct State {
    size: f64,
    shape: f64,
}

/// What a conduit's profile is drawn from.
pub struct ConduitPassage<'a> {
    pub nodes: &'a [Node],
    pub chain: &'a [u32],
    pub types: &'a [ConduitType],
    /// The radius process's value at each node of the chain.
    pub radius: &'a [f64],
    /// Whether each node of the chain is a junction.
    pub junction: Vec<bool>,
    /// The conduit's flow factor ([`flow_factors`]).
    pub flow: f64,
}

/// Passage profiles, drawn in conduit order.
pub struct PassageProfiles {
    rng: Random,
    /// The processes' state already drawn at each node, so that a conduit starting at a node
    /// another one passed continues from it.
    state: Vec<Option<State>>,
}

impl PassageProfiles {
    pub fn new(seed: u64, node_count: usize) -> Self {
        PassageProfiles { rng: Random::stream(seed, "skeleton", "passages"), state: vec![None; node_count] }
    }

    /// The profile of one conduit, and its radius at each node (the profile's there).
    pub fn conduit(&mut self, c: &ConduitPassage) -> (Vec<ProfilePoint>, Vec<f64>) {
        let at = |i: usize| DVec3::from_array(c.nodes[c.chain[i] as usize].position);
        let lengths: Vec<f64> = (1..c.chain.len()).map(|i| at(i - 1).distance(at(i))).collect();
        let total: f64 = lengths.iter().sum();
        let node_at: Vec<f64> = std::iter::once(0.0)
            .chain(lengths.iter().scan(0.0, |s, l| {
                *s += l;
                Some(*s)
            }))
            .collect();
        let junctions: Vec<f64> =
            c.junction.iter().zip(&node_at).filter(|(j, _)| **j).map(|(_, s)| *s).collect();
        let mut state = match self.state[c.chain[0] as usize] {
            Some(s) => s,
            None => State { size: self.normal(), shape: self.normal() },
        };
        let flow = c.flow;
        let mut profile = Vec::new();
        let mut node_points = Vec::with_capacity(c.chain.len());
        let mut last = 0.0;
        for (i, &length) in lengths.iter().enumerate() {
            let steps = (length / SPACING).ceil().max(1.0) as usize;
            for k in 0..steps {
                let t = k as f64 / steps as f64;
                let s = node_at[i] + length * t;
                state = self.advance(state, s - last);
                last = s;
                if k == 0 {
                    self.state[c.chain[i] as usize].get_or_insert(state);
                }
                let base = c.radius[i] + (c.radius[i + 1] - c.radius[i]) * t;
                let bias = if k == 0 && i > 0 {
                    0.5 * (shape_bias(c.types[i - 1]) + shape_bias(c.types[i]))
                } else {
                    shape_bias(c.types[i])
                };
                if k == 0 {
                    node_points.push(profile.len());
                }
                profile.push(point(s, base, state, bias, flow * widening(s, &junctions, base)));
            }
        }
        let end = c.chain.len() - 1;
        state = self.advance(state, total - last);
        self.state[c.chain[end] as usize].get_or_insert(state);
        let bias = shape_bias(c.types[end - 1]);
        let last_point =
            point(total, c.radius[end], state, bias, flow * widening(total, &junctions, c.radius[end]));
        node_points.push(profile.len());
        profile.push(last_point);
        limit_slopes(&mut profile);
        let at_nodes = node_points.iter().map(|&i| profile[i].radius).collect();
        (profile, at_nodes)
    }

    /// The state `ds` metres further on.
    fn advance(&mut self, state: State, ds: f64) -> State {
        let rho = (-ds / CORRELATION).exp();
        let keep = (1.0 - rho * rho).sqrt();
        State {
            size: rho * state.size + keep * self.normal(),
            shape: rho * state.shape + keep * self.normal(),
        }
    }

    /// A standard normal draw (Box–Muller).
    fn normal(&mut self) -> f64 {
        let u = 1.0 - self.rng.uniform();
        let v = self.rng.uniform();
        (-2.0 * u.ln()).sqrt() * (std::f64::consts::TAU * v).cos()
    }
}

/// The profile point at arc length `at` with the radius process's value `base`.
fn point(at: f64, base: f64, state: State, bias: f64, factor: f64) -> ProfilePoint {
    let size = (SIZE_SPREAD * heavy(state.size)).exp() / rms_size_factor();
    let ratio = (SHAPE_SPREAD * heavy(state.shape) + bias).exp().clamp(RATIO_LIMITS[0], RATIO_LIMITS[1]);
    let room = (ROOM * base * factor).max(MIN_HALF_WIDTH);
    let radius = (base * size * factor / ratio.sqrt()).clamp(MIN_HALF_WIDTH, room);
    let height = (radius * ratio).clamp(MIN_HALF_HEIGHT, room);
    ProfilePoint { at, radius, ratio: height / radius }
}

/// Limits how fast the half-width and the half-height change along the profile to [`SLOPE`]
/// metres per metre: each becomes the middle of its largest [`SLOPE`]-Lipschitz minorant and
/// its smallest [`SLOPE`]-Lipschitz majorant (a forward and a backward pass each), the
/// [`SLOPE`]-Lipschitz profile nearest the drawn one in the largest difference. Rooms then open
/// and pinches close over several metres; they stay at least [`MIN_HALF_WIDTH`] and
/// [`MIN_HALF_HEIGHT`].
fn limit_slopes(profile: &mut [ProfilePoint]) {
    let at: Vec<f64> = profile.iter().map(|p| p.at).collect();
    let width = lipschitz_middle(&at, profile.iter().map(|p| p.radius).collect());
    let height = lipschitz_middle(&at, profile.iter().map(|p| p.radius * p.ratio).collect());
    for ((p, w), h) in profile.iter_mut().zip(width).zip(height) {
        p.radius = w;
        p.ratio = h / w;
    }
}

/// The middle of the largest [`SLOPE`]-Lipschitz function below `values` and the smallest
/// above them, at the increasing abscissae `at`.
fn lipschitz_middle(at: &[f64], values: Vec<f64>) -> Vec<f64> {
    let envelope = |mut v: Vec<f64>, pick: fn(f64, f64) -> f64, sign: f64| {
        for i in 1..v.len() {
            v[i] = pick(v[i], v[i - 1] + sign * SLOPE * (at[i] - at[i - 1]));
        }
        for i in (0..v.len().saturating_sub(1)).rev() {
            v[i] = pick(v[i], v[i + 1] + sign * SLOPE * (at[i + 1] - at[i]));
        }
        v
    };
    let below = envelope(values.clone(), f64::min, 1.0);
    let above = envelope(values, f64::max, -1.0);
    below.iter().zip(&above).map(|(b, a)| 0.5 * (a + b)).collect()
}

/// 1 + [`JUNCTION_WIDENING`]·exp(−d / r), d the distance to the nearest junction along the
/// conduit.
fn widening(at: f64, junctions: &[f64], radius: f64) -> f64 {
    let d = junctions.iter().map(|j| (at - j).abs()).fold(f64::INFINITY, f64::min);
    1.0 + JUNCTION_WIDENING * (-d / radius.max(MIN_HALF_WIDTH)).exp()
}

/// Tukey's h transform of a standard normal clamped to ±[`Z_MAX`], scaled back to unit
/// variance: the variance of z·exp(τz²/2) is (1 − 2τ)^(−3/2) (the clamp changes it by less than
/// a percent).
fn heavy(z: f64) -> f64 {
    let z = z.clamp(-Z_MAX, Z_MAX);
    z * (TAIL * z * z / 2.0).exp() * (1.0 - 2.0 * TAIL).powf(0.75)
}

/// √E[exp(2σ h(z))] for z standard normal, σ = [`SIZE_SPREAD`] (midpoint rule over ±8; finite
/// because of the clamp): dividing the size by it keeps the mean of its square, the area.
fn rms_size_factor() -> f64 {
    const STEPS: usize = 1600;
    let dz = 16.0 / STEPS as f64;
    (0..STEPS)
        .map(|i| {
            let z = -8.0 + (i as f64 + 0.5) * dz;
            (2.0 * SIZE_SPREAD * heavy(z)).exp() * (-z * z / 2.0).exp() * dz
        })
        .sum::<f64>()
        .sqrt()
        / std::f64::consts::TAU.sqrt().sqrt()
}

/// Each conduit's flow factor: 0.6 + 0.5·√s for its share s of the routes' total weight
/// ([`flow_shares`]), divided by the root mean square of these factors over the network, each
/// conduit weighted by its length, so that the network's mean cross-section area stays the
/// radius process's (as [`rms_size_factor`] keeps it along a passage): the trunk is larger and
/// the tributaries smaller than the radius process, the cave as a whole neither.
pub fn flow_factors(chains: &[Vec<u32>], routes: &[Route], nodes: &[Node]) -> Vec<f64> {
    let at = |i: u32| DVec3::from_array(nodes[i as usize].position);
    let lengths: Vec<f64> =
        chains.iter().map(|c| c.windows(2).map(|w| at(w[0]).distance(at(w[1]))).sum()).collect();
    let factors: Vec<f64> =
        flow_shares(chains, routes).iter().map(|s| 0.6 + 0.5 * s.clamp(0.0, 1.0).sqrt()).collect();
    let total: f64 = lengths.iter().sum();
    if total <= 0.0 {
        return factors;
    }
    let rms = (factors.iter().zip(&lengths).map(|(f, l)| f * f * l).sum::<f64>() / total).sqrt();
    factors.iter().map(|f| f / rms).collect()
}

/// Each conduit's share of the routes' total weight: the weight of the routes through its
/// first segment over the sum of all routes' weights (0 without routes).
fn flow_shares(chains: &[Vec<u32>], routes: &[Route]) -> Vec<f64> {
    let mut through: HashMap<(u32, u32), f64> = HashMap::new();
    for route in routes {
        for w in route.nodes.windows(2) {
            *through.entry((w[0].min(w[1]), w[0].max(w[1]))).or_default() += route.weight;
        }
    }
    let total: f64 = routes.iter().map(|r| r.weight).sum();
    chains
        .iter()
        .map(|chain| {
            let key = (chain[0].min(chain[1]), chain[0].max(chain[1]));
            if total > 0.0 { through.get(&key).copied().unwrap_or(0.0) / total } else { 0.0 }
        })
        .collect()
}

/// Whether each node is a junction: where three or more conduit ends meet.
pub fn junctions(chains: &[Vec<u32>], node_count: usize) -> Vec<bool> {
    let mut ends = vec![0u32; node_count];
    for chain in chains {
        ends[chain[0] as usize] += 1;
        ends[chain[chain.len() - 1] as usize] += 1;
    }
    ends.into_iter().map(|n| n >= 3).collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::Zone;

    fn straight(n: usize, step: f64) -> (Vec<Node>, Vec<u32>) {
        let nodes = (0..n)
            .map(|i| Node {
                position: [i as f64 * step, 0.0, 0.0],
                sample: 0,
                keypoint: None,
                zone: Zone::Vadose,
            })
            .collect();
        (nodes, (0..n as u32).collect())
    }

    fn profile(types: ConduitType, n: usize, step: f64, seed: u64) -> Vec<ProfilePoint> {
        let (nodes, chain) = straight(n, step);
        let types = vec![types; n - 1];
        let radius = vec![2.0; n];
        let passage = ConduitPassage {
            nodes: &nodes,
            chain: &chain,
            types: &types,
            radius: &radius,
            junction: vec![false; n],
            flow: 1.1,
        };
        PassageProfiles::new(seed, n).conduit(&passage).0
    }

    fn sd(values: &[f64]) -> f64 {
        let mean = values.iter().sum::<f64>() / values.len() as f64;
        (values.iter().map(|v| (v - mean).powi(2)).sum::<f64>() / values.len() as f64).sqrt()
    }

    fn lag_correlation(values: &[f64], lag: usize) -> f64 {
        let mean = values.iter().sum::<f64>() / values.len() as f64;
        let pairs = values.len() - lag;
        let c: f64 =
            (0..pairs).map(|i| (values[i] - mean) * (values[i + lag] - mean)).sum::<f64>() / pairs as f64;
        c / sd(values).powi(2)
    }

    #[test]
    fn sizes_vary_by_metres_with_the_spread_of_surveyed_caves() {
        let p = profile(ConduitType::Canyon, 2001, 10.0, 7);
        assert_eq!(p.len(), 5 * 2000 + 1);
        assert!(p.windows(2).all(|w| (w[1].at - w[0].at - 2.0).abs() < 1e-9));
        let ln_width: Vec<f64> = p.iter().map(|q| q.radius.ln()).collect();
        let spread = sd(&ln_width);
        // The 0.5 m floor clamps the low tail of this 2 m conduit (the survey of the default
        // scene measures 0.91).
        assert!((0.65..1.1).contains(&spread), "sd ln width {spread}");
        // Points are 2 m apart: lag 2 is a survey's 4 m, lag 25 is 50 m.
        let near = lag_correlation(&ln_width, 2);
        assert!((0.3..0.75).contains(&near), "correlation at 4 m {near}");
        assert!(lag_correlation(&ln_width, 25).abs() < 0.15);
        // The size factor keeps the mean area (half-width times half-height) of the drawn sizes
        // that of the radius process; the room cap and the slope limit take area out of the
        // largest rooms, but not most of it.
        let mean_area: f64 = p.iter().map(|q| q.radius * q.radius * q.ratio).sum::<f64>() / p.len() as f64;
        let expected = (2.0 * 1.1f64).powi(2);
        assert!((0.5..1.0).contains(&(mean_area / expected)), "{mean_area}");
    }

    #[test]
    fn sizes_change_by_at_most_the_slope_and_rooms_are_capped() {
        let p = profile(ConduitType::Canyon, 2001, 10.0, 11);
        let height = |q: &ProfilePoint| q.radius * q.ratio;
        for w in p.windows(2) {
            let ds = w[1].at - w[0].at;
            assert!((w[1].radius - w[0].radius).abs() <= SLOPE * ds + 1e-9, "{w:?}");
            assert!((height(&w[1]) - height(&w[0])).abs() <= SLOPE * ds + 1e-9, "{w:?}");
        }
        // The profile's radius is 2 m and its flow factor 1.1.
        let room = ROOM * 2.0 * 1.1;
        assert!(p.iter().all(|q| q.radius <= room + 1e-9 && height(q) <= room + 1e-9));
        assert!(p.iter().all(|q| q.radius >= MIN_HALF_WIDTH - 1e-12 && height(q) >= MIN_HALF_HEIGHT - 1e-12));
    }

    #[test]
    fn the_limiter_is_the_middle_of_the_two_envelopes() {
        let at = [0.0, 2.0, 4.0, 6.0, 8.0];
        // A single-point room of 20 m between 2 m sections: the minorant rises to 4 m there,
        // the majorant keeps the 20 m and falls 2 m per point around it.
        let limited = lipschitz_middle(&at, vec![2.0, 2.0, 20.0, 2.0, 2.0]);
        assert_eq!(limited, vec![9.0, 10.0, 12.0, 10.0, 9.0]);
        // A profile already within the slope is left as it is.
        let gentle = vec![1.0, 2.0, 3.0, 2.5, 0.5];
        assert_eq!(lipschitz_middle(&at, gentle.clone()), gentle);
    }

    #[test]
    fn beds_are_wider_than_canyons_and_the_profile_is_deterministic() {
        let median = |mut v: Vec<f64>| {
            v.sort_by(f64::total_cmp);
            v[v.len() / 2]
        };
        let bed = profile(ConduitType::Bed, 401, 10.0, 3);
        let canyon = profile(ConduitType::Canyon, 401, 10.0, 3);
        assert!(
            median(bed.iter().map(|p| p.ratio).collect()) < median(canyon.iter().map(|p| p.ratio).collect())
        );
        assert_eq!(bed, profile(ConduitType::Bed, 401, 10.0, 3));
        assert_ne!(bed, profile(ConduitType::Bed, 401, 10.0, 4));
    }

    #[test]
    fn junctions_widen_the_passage() {
        let (nodes, chain) = straight(41, 10.0);
        let types = vec![ConduitType::Tube; 40];
        let radius = vec![2.0; 41];
        let mut junction = vec![false; 41];
        let draw = |junction: Vec<bool>| {
            let passage = ConduitPassage {
                nodes: &nodes,
                chain: &chain,
                types: &types,
                radius: &radius,
                junction,
                flow: 0.6,
            };
            PassageProfiles::new(1, 41).conduit(&passage).0
        };
        let plain = draw(junction.clone());
        junction[20] = true;
        let widened = draw(junction);
        let at = |p: &[ProfilePoint], s: f64| p.iter().find(|q| q.at == s).map(|q| q.radius).unwrap();
        let (wide, narrow) = (at(&widened, 200.0), at(&plain, 200.0));
        assert!(
            wide > narrow && (wide / narrow - 1.6).abs() < 1e-9 || narrow == MIN_HALF_WIDTH,
            "{wide} {narrow}"
        );
        assert_eq!(at(&widened, 0.0), at(&plain, 0.0));
    }

    #[test]
    fn flow_shares_and_junctions_of_a_fork() {
        let chains = vec![vec![0, 1], vec![1, 2], vec![1, 3]];
        let route = |nodes: Vec<u32>, weight: f64| Route {
            sink: "a".into(),
            spring: "s".into(),
            weight,
            nodes,
            cost: 0.0,
        };
        let routes = vec![route(vec![0, 1, 2], 3.0), route(vec![3, 1, 2], 1.0)];
        assert_eq!(flow_shares(&chains, &routes), vec![0.75, 1.0, 0.25]);
        assert_eq!(junctions(&chains, 4), vec![false, true, false, false]);
        // Lengths 10, 10 and 20 m: the factors keep their ratios and a length-weighted mean
        // square of 1.
        let (mut nodes, _) = straight(4, 10.0);
        nodes[3].position = [10.0, 20.0, 0.0];
        let factors = flow_factors(&chains, &routes, &nodes);
        let raw = [0.6 + 0.5 * 0.75f64.sqrt(), 1.1, 0.85];
        let mean_square =
            (10.0 * factors[0].powi(2) + 10.0 * factors[1].powi(2) + 20.0 * factors[2].powi(2)) / 40.0;
        assert!((mean_square - 1.0).abs() < 1e-12, "{factors:?}");
        assert!((factors[1] / factors[2] - raw[1] / raw[2]).abs() < 1e-12, "{factors:?}");
        assert!((factors[0] / factors[1] - raw[0] / raw[1]).abs() < 1e-12, "{factors:?}");
    }

    #[test]
    fn the_heavy_transform_has_unit_variance_and_the_mean_factor_is_exact() {
        let n = 200_000;
        let dz = 16.0 / n as f64;
        let var: f64 = (0..n)
            .map(|i| {
                let z = -8.0 + (i as f64 + 0.5) * dz;
                heavy(z).powi(2) * (-z * z / 2.0).exp() * dz
            })
            .sum::<f64>()
            / std::f64::consts::TAU.sqrt();
        assert!((var - 1.0).abs() < 1e-2, "{var}");
        assert!(rms_size_factor() > (SIZE_SPREAD * SIZE_SPREAD).exp());
    }
}
