//! `[skeleton]`: the conduit network, by Paris et al. 2021's γ-skeleton (`mode = "gamma"`) or
//! KarstNSim's vadose-then-phreatic routing (`mode = "karstnsim"`, the default).

use serde::{Deserialize, Serialize};

use crate::validate::{Checks, MAX_LENGTH, MIN_LENGTH};

#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct SkeletonParams {
    /// How the network is synthesized.
    pub mode: Mode,
    /// γ of the γ-skeleton rule (gamma mode): a–b is kept unless some key point k has
    /// d(a,k)^γ + d(k,b)^γ < d(a,b)^γ. 2: Gabriel-like, large: relative neighbourhood graph.
    pub gamma: f64,
    /// Key-point pairs always joined by a conduit (gamma mode), by name.
    pub forced_links: Vec<[String; 2]>,
    /// KarstNSim's P_red in the vadose zone: edges already used cost this fraction (0, 1].
    pub cohesion_vadose: f64,
    /// P_red in the phreatic zone.
    pub cohesion_phreatic: f64,
    /// Amplification (Paris et al. 2021 §5.2): steps of new key points drawn in the bedrock of
    /// the network's bounding box and joined to it.
    pub amplification_steps: usize,
    /// New key points of the first amplification step. Absent: one per
    /// thirty sampling radii of routed conduit (docs/skeleton.md, "Defaults from the scene").
    #[serde(skip_serializing_if = "Option::is_none")]
    pub amplification_points: Option<usize>,
    /// Fraction of the new key points that are dead ends (joined once); the others are interior
    /// points (joined at two places, closing loops). Default [`DEFAULT_DEAD_END_FRACTION`].
    pub dead_end_fraction: f64,
    /// Range `[min, max]` of the length of the first step's amplification branches, metres:
    /// each new key point is drawn at a distance from an anchor on the network that follows a
    /// power law over this range (each later step divides max by `amplification_ratio`).
    /// Absent: derived from the sampling radius and the sinks' spacing (docs/skeleton.md).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub amplification_length: Option<[f64; 2]>,
    /// Exponent α of that power law, P(length > ℓ) ∝ ℓ^−α: small α, heavier tail.
    pub amplification_exponent: f64,
    /// Horton ratio R of the amplification: step s draws `amplification_points` × R^s points,
    /// and with R > 1 they branch off the previous step's branches. 1: every step alike.
    pub amplification_ratio: f64,
    /// Probability that a new branch starts at a confluence of the previous step (mixing
    /// corrosion) rather than anywhere along the branches it grows from.
    pub confluence_attraction: f64,
    /// θ in [0, 1]: amplitude of the tortuosity added by midpoint displacement, from a few
    /// centimetres (0) to 4 m (1). Absent: conduits keep the straight links of the graph.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub tortuosity: Option<f64>,
    /// Sinuosity of the meanders conduits make in their bedding plane (arc length over chord of
    /// each meander, ≥ 1); 1: no meanders.
    pub sinuosity: f64,
    /// Range `[min, max]` of the meander wavelength, metres, drawn per conduit. Absent: ten
    /// passage widths (2 × `radius`).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub meander_wavelength: Option<[f64; 2]>,
    /// Midpoint-displacement levels (each doubles the segments of a conduit).
    pub tortuosity_levels: u32,
    /// Range `[min, max]` of conduit radii, metres, outside the epikarst: a Gaussian process
    /// along each conduit, with uniform marginals over the range.
    pub radius: [f64; 2],
    /// Range `[min, max]` of the correlation length of the radius process, metres; each
    /// conduit draws its own.
    pub radius_correlation: [f64; 2],
    /// Radius of epikarst segments, metres.
    pub epikarst_radius: f64,
    /// Segments whose midpoint has a karstification potential at or above this are chambers
    /// (ghost rock: Paris et al.'s resistance ≈ 0). Absent: no chambers.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub ghost_rock_potential: Option<f64>,
    /// Segments steeper than this (degrees from horizontal) are shafts: epikarst or tube.
    pub vertical_angle: f64,
    /// Shafts starting within this depth below the ground are epikarst, metres.
    pub epikarst_depth: f64,
    /// Gently sloping vadose segments within this height above the water table are keyholes.
    pub keyhole_height: f64,
}

impl Default for SkeletonParams {
    fn default() -> Self {
        SkeletonParams {
            mode: Mode::Karstnsim,
            gamma: 2.0,
            forced_links: Vec::new(),
            cohesion_vadose: DEFAULT_COHESION_VADOSE,
            cohesion_phreatic: DEFAULT_COHESION_PHREATIC,
            amplification_steps: 3,
            amplification_points: None,
            dead_end_fraction: DEFAULT_DEAD_END_FRACTION,
            amplification_length: None,
            amplification_exponent: 1.0,
            amplification_ratio: 2.0,
            confluence_attraction: 1.0,
            tortuosity: None,
            tortuosity_levels: 2,
            sinuosity: 1.15,
            meander_wavelength: None,
            radius: [0.5, 4.0],
            radius_correlation: [50.0, 200.0],
            epikarst_radius: 0.5,
            ghost_rock_potential: None,
            vertical_angle: 60.0,
            epikarst_depth: 15.0,
            keyhole_height: 10.0,
        }
    }
}

/// How the network is synthesized.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Mode {
    /// Paris et al. 2021 §5.1: the γ-skeleton of the key points, each kept pair joined by its
    /// least-cost path.
    Gamma,
    /// KarstNSim §1.4: every sink routed to its spring's water table, then to the spring.
    Karstnsim,
}

/// KarstNSim's P_red in the vadose zone (Gouy et al. 2024's examples): conduit piracy merges the
/// sinks' paths into trunks.
pub const DEFAULT_COHESION_VADOSE: f64 = 0.7;
/// KarstNSim's P_red in the phreatic zone, stronger: phreatic conduits capture the flow around
/// them.
pub const DEFAULT_COHESION_PHREATIC: f64 = 0.4;
/// Share of the amplification's side passages that end blind; the other 15 % reconnect and close
/// loops. A tree's central point dominance is at least about 0.5 (the junction where its halves
/// meet lies on half of all paths) and was above the real maximum (0.572) on a quarter of the
/// realism population's tuning realizations with no loops; connected surveyed caves have mean
/// degrees 2.0–2.17 (KNdata-public), a few loops per hundred branches.
pub const DEFAULT_DEAD_END_FRACTION: f64 = 0.85;

/// Largest γ (γ = 50 already keeps only the relative neighbourhood graph's pairs).
pub const MAX_GAMMA: f64 = 100.0;
/// Most amplification steps.
pub const MAX_AMPLIFICATION_STEPS: usize = 100;
/// Most new key points per amplification step.
pub const MAX_AMPLIFICATION_POINTS: usize = 10_000;
/// Most new key points over all amplification steps.
pub const MAX_AMPLIFICATION_WORK: usize = 100_000;

impl SkeletonParams {
    pub(crate) fn check(&self, c: &mut Checks) {
        if c.within("skeleton.gamma", self.gamma, 0.0, MAX_GAMMA) && self.gamma == 0.0 {
            c.report("skeleton.gamma", format!("must be > 0, got {}", self.gamma));
        }
        if self.amplification_steps > MAX_AMPLIFICATION_STEPS {
            c.report(
                "skeleton.amplification_steps",
                format!("must be at most {MAX_AMPLIFICATION_STEPS}, got {}", self.amplification_steps),
            );
        }
        if let Some(points) = self.amplification_points.filter(|p| *p > MAX_AMPLIFICATION_POINTS) {
            c.report(
                "skeleton.amplification_points",
                format!("must be at most {MAX_AMPLIFICATION_POINTS}, got {points}"),
            );
        }
        let new_points = self.amplification_steps.saturating_mul(self.amplification_points.unwrap_or(0));
        if new_points > MAX_AMPLIFICATION_WORK {
            // One or two least-cost searches per new point.
            c.report(
                "skeleton.amplification_points",
                format!(
                    "amplification_steps × amplification_points = {new_points} new key points, each one or two least-cost \
                     searches: at most {MAX_AMPLIFICATION_WORK}; {} points per step would fit",
                    MAX_AMPLIFICATION_WORK / self.amplification_steps.max(1)
                ),
            );
        }
        for (field, p) in [
            ("skeleton.cohesion_vadose", self.cohesion_vadose),
            ("skeleton.cohesion_phreatic", self.cohesion_phreatic),
        ] {
            if c.finite(field, &[p]) && !(p > 0.0 && p <= 1.0) {
                c.report(field, format!("P_red must be in (0, 1], got {p}"));
            }
        }
        c.within("skeleton.dead_end_fraction", self.dead_end_fraction, 0.0, 1.0);
        if let Some(range) = self.amplification_length {
            c.range("skeleton.amplification_length", range, MIN_LENGTH, MAX_LENGTH);
        }
        c.positive("skeleton.amplification_exponent", self.amplification_exponent);
        c.within("skeleton.amplification_ratio", self.amplification_ratio, 1.0, 10.0);
        c.within("skeleton.confluence_attraction", self.confluence_attraction, 0.0, 1.0);
        c.within("skeleton.sinuosity", self.sinuosity, 1.0, 3.0);
        if let Some(range) = self.meander_wavelength {
            c.range("skeleton.meander_wavelength", range, MIN_LENGTH, MAX_LENGTH);
        }
        if let Some(theta) = self.tortuosity
            && c.finite("skeleton.tortuosity", &[theta])
            && !(0.0..=1.0).contains(&theta)
        {
            c.report("skeleton.tortuosity", format!("θ must be in [0, 1], got {theta}"));
        }
        if self.tortuosity_levels > 6 {
            c.report(
                "skeleton.tortuosity_levels",
                format!("must be at most 6, got {}", self.tortuosity_levels),
            );
        }
        c.range("skeleton.radius", self.radius, super::MIN_RADIUS, super::MAX_RADIUS);
        if c.finite("skeleton.vertical_angle", &[self.vertical_angle])
            && !(self.vertical_angle > 0.0 && self.vertical_angle <= 90.0)
        {
            c.report(
                "skeleton.vertical_angle",
                format!("must be in (0, 90] degrees, got {}", self.vertical_angle),
            );
        }
        let [c0, _] = self.radius_correlation;
        c.range("skeleton.radius_correlation", self.radius_correlation, 0.0, MAX_LENGTH);
        if c0 == 0.0 {
            c.report("skeleton.radius_correlation", "must be > 0, got 0".into());
        }
        c.within("skeleton.epikarst_radius", self.epikarst_radius, super::MIN_RADIUS, super::MAX_RADIUS);
        if let Some(g) = self.ghost_rock_potential
            && c.finite("skeleton.ghost_rock_potential", &[g])
            && !(0.0..=1.0).contains(&g)
        {
            c.report("skeleton.ghost_rock_potential", format!("must be in [0, 1], got {g}"));
        }
        c.non_negative("skeleton.epikarst_depth", self.epikarst_depth);
        c.non_negative("skeleton.keyhole_height", self.keyhole_height);
    }
}
