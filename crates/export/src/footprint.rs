//! A conduit segment seen from above: its footprint on the map and its roof.
//!
//! A segment is a tube whose radius varies linearly from one end to the other (the union of the
//! spheres centred on its axis), so its footprint is the set of map points within the
//! interpolated radius of the axis's projection: the convex hull of the two end discs. The
//! GeoPackage's `passages` layer draws that hull ([`SegmentFootprint::outline`]) and the
//! rasters test pixels against the same set ([`SegmentFootprint::over_pixel`]), so that a map
//! and a raster of one run agree.

use karst_skeleton::Skeleton;

use crate::network::NetworkView;

/// One segment's tube: its axis ends (local coordinates, metres) and their radii.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SegmentFootprint {
    pub ends: [[f64; 3]; 2],
    pub radius: [f64; 2],
}

/// What a tube holds above one map point: the top of its roof and the bottom of its floor.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Column {
    pub roof: f64,
    pub floor: f64,
}

impl SegmentFootprint {
    /// Every segment of the network, in segment order (self-loops included: they are a disc).
    pub fn all(net: &NetworkView) -> Vec<SegmentFootprint> {
        net.segments
            .iter()
            .map(|s| SegmentFootprint {
                ends: s.nodes.map(|n| net.nodes[n as usize].position),
                radius: s.radius,
            })
            .collect()
    }

    /// Every segment of a skeleton with the skeleton's radii (a run without hydro's sizing).
    pub fn of_skeleton(skeleton: &Skeleton) -> Vec<SegmentFootprint> {
        let position = |n: u32| skeleton.nodes[n as usize].position;
        skeleton
            .conduits
            .iter()
            .flat_map(|c| {
                c.nodes.windows(2).zip(c.radius.windows(2)).map(move |(n, r)| SegmentFootprint {
                    ends: [position(n[0]), position(n[1])],
                    radius: [r[0], r[1]],
                })
            })
            .collect()
    }

    /// The map box `[[min x, min y], [max x, max y]]` holding the footprint.
    pub fn bounds(&self) -> [[f64; 2]; 2] {
        let [a, b] = self.ends;
        let [ra, rb] = self.radius;
        [
            [(a[0] - ra).min(b[0] - rb), (a[1] - ra).min(b[1] - rb)],
            [(a[0] + ra).max(b[0] + rb), (a[1] + ra).max(b[1] + rb)],
        ]
    }

    /// The vertical extent of the tube over the square pixel of centre `(x, y)` and edge
    /// `2 half`, None when the footprint misses the pixel. The tube's section at axis
    /// parameter t is a sphere; over the square it reaches highest (and lowest) at the
    /// square's point nearest to the sphere's centre. That is evaluated along the part of
    /// the axis whose spheres can reach the square, every 1/32 of a pixel (at most 512
    /// steps).
    pub fn over_pixel(&self, x: f64, y: f64, half: f64) -> Option<Column> {
        let [t0, t1] =
            self.reach(x, y, self.radius[0].max(self.radius[1]) + half * std::f64::consts::SQRT_2)?;
        let [a, b] = self.ends;
        let length = (0..3).map(|i| (b[i] - a[i]).powi(2)).sum::<f64>().sqrt();
        let steps = ((t1 - t0) * length / (half / 16.0)).ceil().clamp(1.0, 512.0) as usize;
        let mut column: Option<Column> = None;
        for k in 0..=steps {
            let t = t0 + (t1 - t0) * k as f64 / steps as f64;
            let centre: [f64; 3] = std::array::from_fn(|i| a[i] + (b[i] - a[i]) * t);
            let r = self.radius[0] + (self.radius[1] - self.radius[0]) * t;
            let near = [centre[0].clamp(x - half, x + half), centre[1].clamp(y - half, y + half)];
            let d2 = (near[0] - centre[0]).powi(2) + (near[1] - centre[1]).powi(2);
            if d2 > r * r {
                continue;
            }
            let rise = (r * r - d2).sqrt();
            let (roof, floor) = (centre[2] + rise, centre[2] - rise);
            column = Some(match column {
                Some(c) => Column { roof: c.roof.max(roof), floor: c.floor.min(floor) },
                None => Column { roof, floor },
            });
        }
        column
    }

    /// The axis parameters `[t0, t1]` ⊂ [0, 1] whose map projection lies within `reach` of
    /// `(x, y)`, None when none does.
    fn reach(&self, x: f64, y: f64, reach: f64) -> Option<[f64; 2]> {
        let [a, b] = self.ends;
        let d = [b[0] - a[0], b[1] - a[1]];
        let f = [a[0] - x, a[1] - y];
        let qa = d[0] * d[0] + d[1] * d[1];
        let qb = 2.0 * (f[0] * d[0] + f[1] * d[1]);
        let qc = f[0] * f[0] + f[1] * f[1] - reach * reach;
        if qa == 0.0 {
            return (qc <= 0.0).then_some([0.0, 1.0]);
        }
        let discriminant = qb * qb - 4.0 * qa * qc;
        if discriminant < 0.0 {
            return None;
        }
        let root = discriminant.sqrt();
        let (t0, t1) = (((-qb - root) / (2.0 * qa)).max(0.0), ((-qb + root) / (2.0 * qa)).min(1.0));
        (t0 <= t1).then_some([t0, t1])
    }

    /// The footprint's outline, counter-clockwise and closed (first point repeated): the convex
    /// hull of the two end discs, each drawn with `sides` points.
    pub fn outline(&self, sides: usize) -> Vec<[f64; 2]> {
        let mut points: Vec<[f64; 2]> = Vec::with_capacity(2 * sides);
        for (end, r) in self.ends.iter().zip(self.radius) {
            for k in 0..sides {
                let angle = std::f64::consts::TAU * k as f64 / sides as f64;
                points.push([end[0] + r * angle.cos(), end[1] + r * angle.sin()]);
            }
        }
        let mut hull = convex_hull(points);
        hull.push(hull[0]);
        hull
    }
}

/// The convex hull of `points`, counter-clockwise from the lowest-leftmost (Andrew's monotone
/// chain).
fn convex_hull(mut points: Vec<[f64; 2]>) -> Vec<[f64; 2]> {
    points.sort_by(|p, q| p[0].total_cmp(&q[0]).then(p[1].total_cmp(&q[1])));
    points.dedup();
    if points.len() < 3 {
        return points;
    }
    let cross =
        |o: [f64; 2], a: [f64; 2], b: [f64; 2]| (a[0] - o[0]) * (b[1] - o[1]) - (a[1] - o[1]) * (b[0] - o[0]);
    let mut hull: Vec<[f64; 2]> = Vec::with_capacity(points.len() + 1);
    for pass in [&points[..], &points.iter().rev().copied().collect::<Vec<_>>()[..]] {
        let start = hull.len();
        for &p in pass {
            while hull.len() >= start + 2 && cross(hull[hull.len() - 2], hull[hull.len() - 1], p) <= 0.0 {
                hull.pop();
            }
            hull.push(p);
        }
        hull.pop();
    }
    hull
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_tube_covers_the_pixels_within_its_radius() {
        let tube = SegmentFootprint { ends: [[0.0, 0.0, 10.0], [10.0, 0.0, 20.0]], radius: [1.0, 3.0] };
        let tiny = 1e-3;
        let mid = tube.over_pixel(5.0, 0.0, tiny).expect("on the axis");
        // The spheres along the widening, rising axis reach 55/3 above (5, 0) and 12.5 below it
        // (maximum of 10 + 10t ± √((1 + 2t)² − (10t − 5)²)).
        assert!((mid.roof - 55.0 / 3.0).abs() < 1e-2 && (mid.floor - 12.5).abs() < 1e-2, "{mid:?}");
        assert!(tube.over_pixel(5.0, 1.9, tiny).is_some() && tube.over_pixel(5.0, 2.1, tiny).is_none());
        assert!(tube.over_pixel(-0.9, 0.0, tiny).is_some() && tube.over_pixel(-1.1, 0.0, tiny).is_none());
        assert!(tube.over_pixel(12.9, 0.0, tiny).is_some() && tube.over_pixel(13.1, 0.0, tiny).is_none());
        let pixel = tube.over_pixel(5.0, 6.0, 5.0).expect("the pixel's south edge crosses the tube");
        assert!((pixel.roof - (20.0 + 8f64.sqrt())).abs() < 1e-9, "at the wide end, {pixel:?}");
        assert!(tube.over_pixel(5.0, 8.5, 5.0).is_none(), "3.5 m from the axis, the largest radius is 3");
        let shaft = SegmentFootprint { ends: [[0.0, 0.0, 0.0], [0.0, 0.0, 50.0]], radius: [2.0, 2.0] };
        let c = shaft.over_pixel(1.0, 0.0, tiny).unwrap();
        assert!(
            (c.roof - (50.0 + 3f64.sqrt())).abs() < 1e-2 && (c.floor + 3f64.sqrt()).abs() < 1e-2,
            "{c:?}"
        );
    }

    #[test]
    fn the_outline_is_the_hull_of_the_end_discs() {
        let tube = SegmentFootprint { ends: [[0.0, 0.0, 0.0], [10.0, 0.0, 0.0]], radius: [1.0, 1.0] };
        let ring = tube.outline(16);
        assert_eq!(ring.first(), ring.last());
        let area: f64 = ring.windows(2).map(|w| w[0][0] * w[1][1] - w[1][0] * w[0][1]).sum::<f64>() / 2.0;
        let expected = 20.0 + std::f64::consts::PI;
        assert!(area > 0.0 && (area - expected).abs() < 0.05 * expected, "counter-clockwise, {area}");
        let [min, max] = tube.bounds();
        assert_eq!([min, max], [[-1.0, -1.0], [11.0, 1.0]]);
    }
}
