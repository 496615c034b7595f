//! Segment properties (Emilien et al. 2015 §5.2): type from the slope–flow diagram, speed,
//! width and depth.
//!
//! The type is the hydro stage's Table 1 classification ([`karst_hydro::classify`]):
//! slope is the segment's inclination (a fall: its chord's), flow the discharge mapped to flow
//! units on a log scale, `streams.flow_range` going to 1 and 8. A contact segment classified
//! as a free fall, or a fall classified as contact water, keeps the nearest type and is
//! reported (the paper draws it in red).
//!
//! Geometry (§5.2.2): speed δ = k·s; depth ζ = depth_factor·Q^0.4 (the paper's f_d, here the
//! depth's exponent of Leopold and Maddock's hydraulic geometry); width ε from the triangular
//! section's Q = δ·ε·ζ/2 (Eq. 1). A falling sheet keeps the width of the water reaching its
//! lip and is Q/(v·ε) thick at mid-height, v = √(v₀² + g·drop), at least `sheet_thickness`.
//! The plunge pool's depth is Veronese's scour depth 1.9·H^0.225·q^0.54 (H the drop, q = Q/ε
//! per metre of width), at most its radius.

use glam::DVec3;

use karst_hydro::G;
use karst_hydro::{FlowScale, WaterType, classify};
use karst_scene::params::StreamsParams;

use crate::network::Network;
use crate::payload::{Motion, Segment};

/// The properties of every edge of `net` carrying `flow`.
pub fn segments(
    net: &Network,
    flow: &[f64],
    params: &StreamsParams,
    reports: &mut Vec<String>,
) -> Vec<Segment> {
    let scale = FlowScale { min: params.flow_range[0], max: params.flow_range[1] };
    let mut out: Vec<Segment> = net
        .edges
        .iter()
        .zip(flow)
        .map(|(e, &q)| {
            let (a, b) = (net.positions[e.from as usize], net.positions[e.to as usize]);
            let slope = inclination(a, b);
            let units = if q > 0.0 { scale.units(q) } else { 0.0 };
            let water = match e.motion {
                Motion::Pool => WaterType::Pool,
                _ if q <= 0.0 => WaterType::Dry,
                _ => classify(slope, units),
            };
            let mut s = Segment {
                from: e.from,
                to: e.to,
                motion: e.motion,
                curve: None,
                flow: q,
                water,
                slope,
                flow_units: units,
                look: water.look(),
                speed: 0.0,
                width: 0.0,
                depth: 0.0,
                fall: e.fall.clone(),
            };
            if e.motion == Motion::Contact && q > 0.0 {
                s.speed = params.speed_factor * slope.max(params.min_slope.atan());
                s.depth = params.depth_factor * q.powf(0.4);
                s.width = 2.0 * q / (s.speed * s.depth);
            }
            s
        })
        .collect();
    for i in 0..out.len() {
        if out[i].motion == Motion::FreeFall && out[i].flow > 0.0 {
            let width = lip_width(net, &out, i, params);
            sheet(&mut out[i], width, params);
        }
    }
    implausible(&out, reports);
    out
}

/// Inclination of a → b, radians in [0, π/2].
pub fn inclination(a: DVec3, b: DVec3) -> f64 {
    let run = a.truncate().distance(b.truncate());
    (a.z - b.z).abs().atan2(run)
}

/// Width of the water reaching the lip of fall `i`: its widest incoming contact segment, or
/// (at a spring's mouth) the width of water running at the lip's speed.
fn lip_width(net: &Network, segments: &[Segment], i: usize, params: &StreamsParams) -> f64 {
    let lip = segments[i].from as usize;
    let widest = net.into[lip]
        .iter()
        .map(|&e| &segments[e as usize])
        .filter(|s| s.motion == Motion::Contact)
        .map(|s| s.width)
        .fold(0.0, f64::max);
    if widest > 0.0 {
        return widest;
    }
    let q = segments[i].flow;
    let speed = segments[i].fall.as_ref().map_or(params.mouth_speed, |f| f.speed.hypot(f.vertical)).max(0.1);
    2.0 * q / (speed * params.depth_factor * q.powf(0.4))
}

fn sheet(s: &mut Segment, width: f64, params: &StreamsParams) {
    let Some(fall) = &s.fall else { return };
    let v0 = fall.speed.hypot(fall.vertical);
    s.speed = (v0 * v0 + G * fall.drop).sqrt();
    s.width = width;
    s.depth = (s.flow / (s.speed * width)).max(params.sheet_thickness);
}

fn implausible(segments: &[Segment], reports: &mut Vec<String>) {
    for (motion, what) in [(Motion::Contact, "contact"), (Motion::FreeFall, "free-fall")] {
        let odd: Vec<usize> = (0..segments.len())
            .filter(|&i| {
                let s = &segments[i];
                s.motion == motion
                    && s.water.look().is_some()
                    && s.water.is_free_fall() != (motion == Motion::FreeFall)
            })
            .collect();
        if let Some(&first) = odd.first() {
            reports.push(format!(
                "{} {what} segment(s) fall in the other half of the slope–flow diagram and keep the \
                 nearest type (first: segments[{first}], {})",
                odd.len(),
                segments[first].water.name()
            ));
        }
    }
}

/// Depth dug by a fall of `drop` metres carrying `q` m³/s in a sheet `width` wide, at most
/// `radius` (Veronese 1937).
pub fn scour_depth(drop: f64, q: f64, width: f64, radius: f64) -> f64 {
    let unit = q / width.max(0.1);
    (1.9 * drop.max(0.0).powf(0.225) * unit.max(0.0).powf(0.54)).clamp(0.3, radius.max(0.3))
}

#[cfg(test)]
mod tests {
    use std::f64::consts::PI;

    use super::*;
    use crate::payload::Role;

    #[test]
    fn eq_1_holds_for_contact_water() {
        let params = StreamsParams::default();
        let mut net = Network::new(2.0);
        let a = net.add_node(DVec3::new(0.0, 0.0, 10.0), Role::Source);
        let b = net.add_node(DVec3::new(10.0, 0.0, 9.0), Role::Well);
        net.add_edge(a, b, Motion::Contact, None, None);
        let s = &segments(&net, &[0.4], &params, &mut Vec::new())[0];
        assert!((s.speed * s.width * s.depth / 2.0 - 0.4).abs() < 1e-12);
        assert!((s.slope - (0.1f64).atan()).abs() < 1e-12);
        assert!(s.slope < PI / 2.0);
    }

    #[test]
    fn the_ten_types_of_table_1_on_hand_built_segments() {
        let params = StreamsParams::default();
        let [q1, q8] = params.flow_range;
        // (type, slope, flow units, in the air)
        let seeds = [
            (WaterType::Ribbon, PI / 2.0, 1.0, true),
            (WaterType::Plunge, PI / 2.0, 2.0, true),
            (WaterType::Ledge, PI / 2.0, 5.0, true),
            (WaterType::Cataract, PI / 2.0, 8.0, true),
            (WaterType::Stream, PI / 16.0, 2.0, false),
            (WaterType::River, PI / 32.0, 5.0, false),
            (WaterType::Rapid, PI / 16.0, 5.0, false),
            (WaterType::Cascade, PI / 8.0, 3.0, false),
            (WaterType::Horsetail, PI / 4.0, 2.0, false),
            (WaterType::Block, PI / 4.0, 6.0, false),
        ];
        let mut net = Network::new(1.0);
        let mut flows = Vec::new();
        for (k, &(_, slope, units, air)) in seeds.iter().enumerate() {
            // Slightly off the seed, still in its cell.
            let slope = if air { slope } else { slope * 1.05 };
            let run = if air { 1e-3 } else { 10.0 };
            let a = net.add_node(DVec3::new(0.0, 20.0 * k as f64, 100.0), Role::Source);
            let b = net
                .add_node(DVec3::new(run, 20.0 * k as f64, 100.0 - run * slope.tan().min(1e6)), Role::Well);
            net.add_edge(a, b, if air { Motion::FreeFall } else { Motion::Contact }, None, None);
            flows.push(q1 * (q8 / q1).powf((units * 1.02 - 1.0) / 7.0));
        }
        let mut reports = Vec::new();
        let segments = segments(&net, &flows, &params, &mut reports);
        for (s, (t, ..)) in segments.iter().zip(&seeds) {
            assert_eq!(s.water, *t, "{}", t.name());
            assert!(s.look.is_some());
        }
        assert!(reports.is_empty(), "{reports:?}");
    }
}
