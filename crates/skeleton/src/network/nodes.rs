//! The network's nodes: a sample (or a point placed by tortuosity) with its key point and the
//! zone of the water tables there.

use karst_geology::{Geology, Point};
use karst_sampling::Samples;

use crate::payload::{Node, Zone};
use crate::view::SkeletonView;

/// Whether `sample` is the sample of a key point (key point i is sample i when present).
pub fn is_keypoint(samples: &Samples, sample: u32) -> bool {
    samples.keypoint_sample(sample as usize) == Some(sample as usize)
}

pub fn node(view: &SkeletonView, samples: &Samples, sample: u32) -> Node {
    let keypoint = view.keypoints.get(sample as usize).filter(|_| is_keypoint(samples, sample));
    node_at(view.geology, samples.positions[sample as usize], sample, keypoint.map(|k| k.name.clone()))
}

/// A node at `position`, in the zone of the water tables there.
pub fn node_at(geology: &Geology, position: [f64; 3], sample: u32, keypoint: Option<String>) -> Node {
    let zone = if is_phreatic(geology, Point::from_array(position)) { Zone::Phreatic } else { Zone::Vadose };
    Node { position, sample, keypoint, zone }
}

/// Whether `p` lies below a water table of the scene.
pub fn is_phreatic(geology: &Geology, p: Point) -> bool {
    geology.water_tables.iter().any(|w| w.height_above(p) < 0.0)
}
