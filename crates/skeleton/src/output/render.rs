//! `karst-skeleton render`: the network picture of karst-plot (top view over side view, one
//! metric scale) with conduits coloured by type, key points marked and named, and a legend of
//! the types present with their lengths.

use karst_plot::legend::{Entry, Swatch};
use karst_plot::network::{KeyPoint, NetworkPicture, Segment};
use karst_plot::{BLACK, Canvas, Rgb, ticks};

use crate::{ConduitType, Skeleton};

/// Width of a conduit on the picture, pixels.
const CONDUIT: f64 = 2.0;

/// Colour of a conduit type.
pub fn colour(kind: ConduitType) -> Rgb {
    match kind {
        ConduitType::Epikarst => [120, 180, 60],
        ConduitType::Tube => [200, 60, 160],
        ConduitType::Canyon => [230, 130, 30],
        ConduitType::Keyhole => [200, 180, 0],
        ConduitType::Passage => [150, 90, 50],
        ConduitType::Bed => [30, 90, 220],
        ConduitType::Chamber => [220, 30, 30],
    }
}

/// Draws `skeleton` (titled `title`).
pub fn render(skeleton: &Skeleton, title: &str) -> Canvas {
    picture(skeleton, title).render()
}

fn picture(skeleton: &Skeleton, title: &str) -> NetworkPicture {
    let position = |i: u32| skeleton.nodes[i as usize].position;
    let segments = skeleton
        .conduits
        .iter()
        .flat_map(|c| {
            c.nodes.windows(2).zip(&c.types).map(move |(w, kind)| Segment {
                a: position(w[0]),
                b: position(w[1]),
                colour: colour(*kind),
                width: CONDUIT,
            })
        })
        .collect();
    let key_points = skeleton
        .nodes
        .iter()
        .filter_map(|n| n.keypoint.as_ref().map(|name| KeyPoint { position: n.position, name: name.clone() }))
        .collect();
    let mut legend: Vec<Entry> = ConduitType::ALL
        .into_iter()
        .filter_map(|kind| {
            let length = skeleton.length_of_type(kind);
            (length > 0.0).then(|| {
                Entry::new(
                    Swatch::Line(colour(kind), 3.0),
                    format!("{} ({} m)", kind.name(), ticks::human(length)),
                )
            })
        })
        .collect();
    legend.push(Entry::new(Swatch::Dot(BLACK), "key point"));
    let notes = vec![format!(
        "{} nodes, {} conduits, {} m in all.",
        skeleton.nodes.len(),
        skeleton.conduits.len(),
        ticks::human(skeleton.total_length())
    )];
    NetworkPicture { title: title.to_string(), segments, key_points, legend, notes }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::{Conduit, Node, Zone};

    fn skeleton() -> Skeleton {
        let node = |p: [f64; 3], k: Option<&str>| Node {
            position: p,
            sample: 0,
            keypoint: k.map(String::from),
            zone: Zone::Vadose,
        };
        Skeleton {
            nodes: vec![
                node([0.0, 0.0, 0.0], Some("a")),
                node([100.0, 0.0, 0.0], None),
                node([100.0, 100.0, 50.0], Some("b")),
            ],
            conduits: vec![Conduit {
                nodes: vec![0, 1, 2],
                radius: vec![1.0; 3],
                types: vec![ConduitType::Bed, ConduitType::Canyon],
                phase: 0,
                keypoints: vec!["a".into(), "b".into()],
                profile: Vec::new(),
            }],
            routes: vec![],
            derived: Default::default(),
        }
    }

    #[test]
    fn conduits_are_drawn_in_their_type_colour() {
        let canvas = render(&skeleton(), "t");
        let count = |c: Rgb| {
            (0..canvas.height() as i64)
                .flat_map(|y| (0..canvas.width() as i64).map(move |x| (x, y)))
                .filter(|&(x, y)| canvas.get(x, y) == Some(c))
                .count()
        };
        assert!(count(colour(ConduitType::Bed)) > 500);
        assert!(count(colour(ConduitType::Canyon)) > 500);
        assert_eq!(count(colour(ConduitType::Tube)), 0);
    }

    #[test]
    fn the_png_decodes_at_the_picture_width() {
        let canvas = render(&skeleton(), "t");
        let mut bytes = Vec::new();
        canvas.encode_png(&mut bytes).unwrap();
        let (w, h, colours) = karst_plot::testing::png_summary(&bytes);
        assert_eq!((w, h), (canvas.width(), canvas.height()));
        assert!((640..=karst_plot::network::WIDTH).contains(&w));
        assert!(h > 600 && colours > 20, "{h} px high, {colours} colours");
    }

    #[test]
    fn the_legend_lists_the_types_present_with_their_lengths() {
        let p = picture(&skeleton(), "t");
        let labels: Vec<&str> = p.legend.iter().map(|e| e.label.as_str()).collect();
        assert_eq!(labels, ["canyon (112 m)", "bed (100 m)", "key point"]);
    }
}
