//! Water types: the slope–flow classification of Emilien et al. 2015 (§3.1, Table 1, Fig. 3,
//! §5.2.1), plus the three states a cave adds: `sump` (a flooded phreatic segment), `pool`
//! (ponded water: a chamber, or a segment where water rises out of a filled low point) and
//! `dry`.
//!
//! A running-water segment takes the type of the nearest Table 1 seed in slope–flow space
//! (a Voronoi cell). The two axes have different units, so both are scaled to [0, 1] before
//! measuring: slope by π/2 (its range) and flow by 7 (the range 1..8 of the seeds' flow units).
//! Network flows are mapped onto flow units logarithmically ([`FlowScale`]): confluences
//! multiply flows, and a log scale keeps a main drain and its tributaries apart.

use std::f64::consts::PI;

use serde::{Deserialize, Serialize};

/// The water of a segment.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum WaterType {
    Stream,
    River,
    Rapid,
    Cascade,
    Horsetail,
    Block,
    Ribbon,
    Plunge,
    Ledge,
    Cataract,
    Sump,
    Pool,
    Dry,
}

/// Foam, rocks, disturbance and particles of a water type (Table 1), each in [0, 1].
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Look {
    pub foam: f64,
    pub rocks: f64,
    pub disturbance: f64,
    pub particles: f64,
}

/// One row of Table 1.
struct Seed {
    water: WaterType,
    slope: f64,
    flow: f64,
    look: Look,
}

const fn seed(water: WaterType, slope: f64, flow: f64, look: [f64; 4]) -> Seed {
    let [foam, rocks, disturbance, particles] = look;
    Seed { water, slope, flow, look: Look { foam, rocks, disturbance, particles } }
}

/// Table 1 of Emilien et al. 2015.
const TABLE_1: [Seed; 10] = [
    seed(WaterType::Ribbon, PI / 2.0, 1.0, [0.0, 0.3, 0.0, 0.0]),
    seed(WaterType::Plunge, PI / 2.0, 2.0, [1.0, 0.4, 0.0, 0.2]),
    seed(WaterType::Ledge, PI / 2.0, 5.0, [0.0, 0.5, 0.0, 0.5]),
    seed(WaterType::Cataract, PI / 2.0, 8.0, [1.0, 1.0, 1.0, 1.0]),
    seed(WaterType::Stream, PI / 16.0, 2.0, [0.0, 0.2, 0.0, 0.0]),
    seed(WaterType::River, PI / 32.0, 5.0, [0.0, 0.2, 0.1, 0.0]),
    seed(WaterType::Rapid, PI / 16.0, 5.0, [0.2, 0.5, 0.5, 0.0]),
    seed(WaterType::Cascade, PI / 8.0, 3.0, [0.5, 1.0, 1.0, 0.0]),
    seed(WaterType::Horsetail, PI / 4.0, 2.0, [1.0, 0.0, 0.0, 0.0]),
    seed(WaterType::Block, PI / 4.0, 6.0, [1.0, 0.0, 0.2, 0.0]),
];

/// Smallest and largest flow unit of the seeds.
pub const UNITS: [f64; 2] = [1.0, 8.0];

impl WaterType {
    /// Every type, in a fixed order.
    pub const ALL: [WaterType; 13] = [
        WaterType::Stream,
        WaterType::River,
        WaterType::Rapid,
        WaterType::Cascade,
        WaterType::Horsetail,
        WaterType::Block,
        WaterType::Ribbon,
        WaterType::Plunge,
        WaterType::Ledge,
        WaterType::Cataract,
        WaterType::Sump,
        WaterType::Pool,
        WaterType::Dry,
    ];

    /// Lowercase name, as in the artifact.
    pub fn name(self) -> &'static str {
        match self {
            WaterType::Stream => "stream",
            WaterType::River => "river",
            WaterType::Rapid => "rapid",
            WaterType::Cascade => "cascade",
            WaterType::Horsetail => "horsetail",
            WaterType::Block => "block",
            WaterType::Ribbon => "ribbon",
            WaterType::Plunge => "plunge",
            WaterType::Ledge => "ledge",
            WaterType::Cataract => "cataract",
            WaterType::Sump => "sump",
            WaterType::Pool => "pool",
            WaterType::Dry => "dry",
        }
    }

    /// Water in the air (right of the red line of Fig. 3).
    pub fn is_free_fall(self) -> bool {
        matches!(self, WaterType::Ribbon | WaterType::Plunge | WaterType::Ledge | WaterType::Cataract)
    }

    /// Foam, rocks, disturbance and particles, for the ten Table 1 types.
    pub fn look(self) -> Option<Look> {
        TABLE_1.iter().find(|s| s.water == self).map(|s| s.look)
    }
}

/// The Table 1 type nearest to (`slope` radians, `units` flow units).
pub fn classify(slope: f64, units: f64) -> WaterType {
    let distance = |s: &Seed| {
        let ds = (slope - s.slope) / (PI / 2.0);
        let dq = (units - s.flow) / (UNITS[1] - UNITS[0]);
        ds * ds + dq * dq
    };
    // The first seed wins ties: the table order is fixed.
    TABLE_1
        .iter()
        .fold((WaterType::Dry, f64::INFINITY), |best, s| {
            let d = distance(s);
            if d < best.1 { (s.water, d) } else { best }
        })
        .0
}

/// Log mapping of network flows in [min, max] onto flow units [1, 8].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FlowScale {
    pub min: f64,
    pub max: f64,
}

impl FlowScale {
    /// Flow units of flow `q` > 0.
    pub fn units(&self, q: f64) -> f64 {
        let span = (self.max / self.min).ln();
        if span.is_nan() || span <= 0.0 {
            return UNITS[1];
        }
        let t = ((q / self.min).ln() / span).clamp(0.0, 1.0);
        UNITS[0] + t * (UNITS[1] - UNITS[0])
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_seed_classifies_as_itself() {
        for s in &TABLE_1 {
            assert_eq!(classify(s.slope, s.flow), s.water, "{}", s.water.name());
        }
    }

    #[test]
    fn vertical_water_always_falls_and_flat_water_runs() {
        for units in [1.0, 1.4, 2.0, 3.5, 5.0, 6.5, 8.0] {
            assert!(classify(PI / 2.0, units).is_free_fall(), "{units}");
            assert!(!classify(0.0, units).is_free_fall(), "{units}");
        }
        assert_eq!(classify(0.0, 1.0), WaterType::Stream);
        assert_eq!(classify(0.0, 8.0), WaterType::River);
        assert_eq!(classify(PI / 2.0, 8.0), WaterType::Cataract);
    }

    #[test]
    fn more_flow_on_the_same_slope_moves_up_the_diagram() {
        // Fig. 3: at a steep slope, a horsetail becomes a block as the flow grows.
        assert_eq!(classify(PI / 4.0, 1.5), WaterType::Horsetail);
        assert_eq!(classify(PI / 4.0, 7.0), WaterType::Block);
    }

    #[test]
    fn flow_scale_is_logarithmic_between_one_and_eight() {
        let s = FlowScale { min: 1.0, max: 100.0 };
        assert_eq!(s.units(1.0), 1.0);
        assert_eq!(s.units(100.0), 8.0);
        assert!((s.units(10.0) - 4.5).abs() < 1e-12);
        assert_eq!(FlowScale { min: 3.0, max: 3.0 }.units(3.0), 8.0);
    }
}
