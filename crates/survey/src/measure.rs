//! One station measured as a surveyor would: in the plane through the station perpendicular to
//! the passage, the open region that holds the centreline point (or, when a wall covers it,
//! the nearest open region), and in it the horizontal and the vertical chord through that
//! point: left + right and up + down.
//!
//! The cave is given by a signed distance bound that is negative inside (the cave alone under
//! the ground, `CarvedTerrain::cave_below_ground`) and 1-Lipschitz, so a walk from an open
//! point along a direction can step by the distance bound and never cross a wall
//! (sphere tracing): it stops within [`TOLERANCE`] of the wall. "Vertical" is the world's up
//! projected into the plane (the sections' own up, docs/sdf.md); in a shaft (steeper than 45°)
//! both chords are horizontal, across and along the shaft's horizontal direction.

use glam::DVec3;

/// How close to the wall a chord ends, metres.
pub const TOLERANCE: f64 = 1e-3;
/// Longest half-chord, metres: beyond, a chord stops (a passage open to the sky, or a shaft
/// seen along its axis).
pub const MAX_HALF_CHORD: f64 = 200.0;
/// Rings of the search for the nearest open point, and directions per ring.
const RINGS: usize = 24;
const DIRECTIONS: usize = 24;

/// The chords measured at one station.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Chords {
    /// The point the chords pass through: the centreline point, or the nearest open one.
    pub centre: DVec3,
    /// The two in-plane directions of the chords: across (horizontal) and up.
    pub axes: [DVec3; 2],
    /// Left + right, metres.
    pub width: f64,
    /// Up + down (or the second horizontal chord in a shaft), metres.
    pub height: f64,
}

/// Whether a passage of direction `tangent` is a shaft: steeper than 45°.
pub fn is_shaft(tangent: DVec3) -> bool {
    tangent.z.abs() > std::f64::consts::FRAC_1_SQRT_2
}

/// The chord directions at a station: across the passage (horizontal) and its section's up
/// (the world's up projected perpendicular to the passage); in a shaft, two horizontal
/// directions, across and along its horizontal course.
pub fn axes(tangent: DVec3) -> [DVec3; 2] {
    let flat = DVec3::new(tangent.x, tangent.y, 0.0);
    let along = if flat.length_squared() > 1e-12 { flat.normalize() } else { DVec3::X };
    let across = DVec3::new(along.y, -along.x, 0.0);
    if is_shaft(tangent) {
        return [across, along];
    }
    let up = DVec3::Z - tangent * tangent.z;
    [across, up.normalize()]
}

/// The chords at `position` of a passage of direction `tangent`, looking for an open point up
/// to `search` metres from it in the plane perpendicular to the passage when the centreline
/// point is in rock. `cave` is negative inside the cave. None when no open point is found.
pub fn measure(cave: &impl Fn(DVec3) -> f64, position: DVec3, tangent: DVec3, search: f64) -> Option<Chords> {
    let axes = axes(tangent);
    let centre = open_point(cave, position, plane(tangent), search)?;
    let chord = |d: DVec3| half_chord(cave, centre, d) + half_chord(cave, centre, -d);
    Some(Chords { centre, axes, width: chord(axes[0]), height: chord(axes[1]) })
}

/// Two unit vectors spanning the plane perpendicular to `tangent`.
pub fn plane(tangent: DVec3) -> [DVec3; 2] {
    let flat = DVec3::new(tangent.x, tangent.y, 0.0);
    let across =
        if flat.length_squared() > 1e-12 { DVec3::new(flat.y, -flat.x, 0.0).normalize() } else { DVec3::X };
    [across, tangent.cross(across).normalize()]
}

/// The point itself when open, else the nearest open point on rings around it in the plane
/// (the deepest one of the first ring that has any).
fn open_point(
    cave: &impl Fn(DVec3) -> f64,
    position: DVec3,
    [u, v]: [DVec3; 2],
    search: f64,
) -> Option<DVec3> {
    if cave(position) < 0.0 {
        return Some(position);
    }
    for ring in 1..=RINGS {
        let r = search * ring as f64 / RINGS as f64;
        let best = (0..DIRECTIONS)
            .map(|k| {
                let a = std::f64::consts::TAU * k as f64 / DIRECTIONS as f64;
                let p = position + (u * a.cos() + v * a.sin()) * r;
                (cave(p), p)
            })
            .filter(|(d, _)| *d < 0.0)
            .min_by(|a, b| a.0.total_cmp(&b.0));
        if let Some((_, p)) = best {
            return Some(p);
        }
    }
    None
}

/// How far from the open point `from` the wall is along the unit direction `d`: sphere
/// tracing on the distance bound.
fn half_chord(cave: &impl Fn(DVec3) -> f64, from: DVec3, d: DVec3) -> f64 {
    let mut t = 0.0;
    while t < MAX_HALF_CHORD {
        let depth = -cave(from + d * t);
        if depth <= TOLERANCE {
            break;
        }
        t += depth;
    }
    t.min(MAX_HALF_CHORD)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// An elliptic tube along the direction (cos 30°, 0, sin 30°) through the origin, with
    /// half-axes 3 m (horizontal) and 1 m (in-plane up): a 1-Lipschitz bound of the distance
    /// (the ellipse's normalised implicit function scaled by its smaller half-axis).
    fn tube(p: DVec3) -> f64 {
        let t = DVec3::new(30f64.to_radians().cos(), 0.0, 30f64.to_radians().sin());
        let [across, up] = axes(t);
        let (x, y) = (p.dot(across), p.dot(up));
        (((x / 3.0).powi(2) + y * y).sqrt() - 1.0) * 1.0
    }

    #[test]
    fn the_chords_of_an_elliptic_tube_are_its_axes() {
        let t = DVec3::new(30f64.to_radians().cos(), 0.0, 30f64.to_radians().sin());
        let c = measure(&tube, DVec3::new(4.0, 0.0, 4.0 * 30f64.to_radians().tan()), t, 2.0).unwrap();
        assert!((c.width - 6.0).abs() < 0.01, "{}", c.width);
        assert!((c.height - 2.0).abs() < 0.01, "{}", c.height);
    }

    #[test]
    fn a_centreline_in_rock_is_measured_in_the_nearest_open_region() {
        let t = DVec3::X;
        // Two round tubes beside the centreline, radii 1 and 2, at 2.5 m and 4 m.
        let cave = |p: DVec3| {
            let a = DVec3::new(0.0, p.y, p.z - 2.5).length() - 1.0;
            let b = DVec3::new(0.0, p.y, p.z + 4.0).length() - 2.0;
            a.min(b)
        };
        let c = measure(&cave, DVec3::ZERO, t, 5.0).unwrap();
        assert!((c.centre.z - 1.5).abs() < 0.25, "{}", c.centre);
        assert!(c.height > 0.0 && c.height <= 2.0 + 1e-6);
        assert_eq!(measure(&cave, DVec3::ZERO, t, 1.0), None);
    }

    #[test]
    fn shafts_carry_two_horizontal_chords() {
        let t = DVec3::new(0.2, 0.0, 1.0).normalize();
        assert!(is_shaft(t));
        let [a, b] = axes(t);
        assert_eq!([a.z, b.z], [0.0, 0.0]);
        assert!(a.dot(b).abs() < 1e-12);
        let shaft = |p: DVec3| (p.x * p.x / 4.0 + p.y * p.y).sqrt() - 1.0;
        let c = measure(&shaft, DVec3::ZERO, t, 1.0).unwrap();
        assert!((c.width - 2.0).abs() < 0.01 && (c.height - 4.0).abs() < 0.01, "{c:?}");
    }
}
