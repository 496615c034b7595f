//! `karst-hydro render`: the network picture of karst-plot (top view over side view, one
//! metric scale, the same picture as `karst-skeleton render`) with each segment coloured by its
//! water type and widened with its flow, dry conduits thin and light grey, key points named,
//! and a legend of the water types present.

use karst_plot::legend::{Entry, Swatch};
use karst_plot::network::{KeyPoint, NetworkPicture, Segment};
use karst_plot::{BLACK, Canvas, Rgb, ticks};
use karst_skeleton::Skeleton;

use crate::payload::Hydro;
use crate::water::WaterType;

/// Colour of a water type: blues for contact water, warm colours for free falls.
pub fn colour(water: WaterType) -> Rgb {
    match water {
        WaterType::Stream => [120, 190, 240],
        WaterType::River => [30, 110, 220],
        WaterType::Rapid => [0, 170, 170],
        WaterType::Cascade => [0, 140, 90],
        WaterType::Horsetail => [150, 200, 60],
        WaterType::Block => [90, 90, 20],
        WaterType::Ribbon => [250, 200, 40],
        WaterType::Plunge => [250, 140, 0],
        WaterType::Ledge => [220, 60, 30],
        WaterType::Cataract => [170, 0, 60],
        WaterType::Sump => [20, 20, 120],
        WaterType::Pool => [160, 80, 200],
        WaterType::Dry => [205, 205, 205],
    }
}

/// Width of a segment, pixels: dry 1, wet 1.5 + 0.5 per flow unit (at least one unit).
fn width(water: WaterType, flow_units: f64) -> f64 {
    if water == WaterType::Dry { 1.0 } else { 1.5 + flow_units.max(1.0) * 0.5 }
}

/// The picture of `hydro` on `skeleton`.
pub fn picture(skeleton: &Skeleton, hydro: &Hydro) -> Canvas {
    network_picture(skeleton, hydro).render()
}

fn network_picture(skeleton: &Skeleton, hydro: &Hydro) -> NetworkPicture {
    let position = |i: u32| skeleton.nodes[i as usize].position;
    let wet_segments = || {
        skeleton.conduits.iter().zip(&hydro.conduits).flat_map(|(c, w)| c.nodes.windows(2).zip(&w.segments))
    };
    // Dry first, so that water is drawn over it.
    let mut segments: Vec<Segment> = Vec::new();
    for dry_pass in [true, false] {
        segments.extend(wet_segments().filter(|(_, s)| (s.water == WaterType::Dry) == dry_pass).map(
            |(n, s)| Segment {
                a: position(n[0]),
                b: position(n[1]),
                colour: colour(s.water),
                width: width(s.water, s.flow_units),
            },
        ));
    }
    let key_points = skeleton
        .nodes
        .iter()
        .filter_map(|n| n.keypoint.as_ref().map(|name| KeyPoint { position: n.position, name: name.clone() }))
        .collect();
    let used = |w: WaterType| wet_segments().any(|(_, s)| s.water == w);
    let mut legend: Vec<Entry> = WaterType::ALL
        .into_iter()
        .filter(|w| used(*w))
        .map(|w| Entry::new(Swatch::Line(colour(w), width(w, 1.0)), w.name()))
        .collect();
    legend.push(Entry::new(Swatch::Dot(BLACK), "key point"));
    let most = wet_segments().map(|(_, s)| s.flow_units).fold(0.0, f64::max);
    let notes = vec![format!(
        "Line width grows with the flow: 1.5 px + 0.5 px per flow unit (Emilien et al. 2015), {} units at most; \
         {} of {} conduits dry.",
        ticks::human(most),
        hydro.conduits.iter().filter(|c| c.dry).count(),
        hydro.conduits.len()
    )];
    NetworkPicture { title: "Water types".into(), segments, key_points, legend, notes }
}
