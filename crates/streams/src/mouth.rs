//! Where a spring's water reaches daylight: the nearest way out of the rock. A spring key
//! point lies at or below the terrain (the end of its conduit). When a valley side or a cliff
//! is nearer horizontally than the ground is above it, the water comes out on that wall at the
//! spring's elevation (the nearest point where the ground is no higher than the spring); when
//! the domain's side is nearer, it leaves the domain there; otherwise it rises to the ground
//! straight above (a rising, Vauclusian spring). A passage from the key point to the mouth
//! joins the conduit to the daylight (carved by the sdf stage). Water leaves a mouth on a wall
//! horizontally, away from the spring, at `streams.mouth_speed`.

use glam::{DVec2, DVec3};

use crate::ground::Ground;

/// A spring's way out.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Daylight {
    Mouth(Mouth),
    /// The domain's side at this point is nearer than any ground: the water leaves the domain.
    Side(DVec3),
}

/// A mouth on the terrain.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Mouth {
    /// On the ground, at the spring's elevation (or on the ground above the spring).
    pub point: DVec3,
    /// Horizontal direction the water leaves in.
    pub direction: DVec2,
}

/// The spring is this close below the ground, metres: it is at the surface already.
const AT_SURFACE: f64 = 0.5;

/// The way out of a spring at `spring`, searched on rings `spacing` apart.
pub fn find(ground: &Ground, spring: DVec3, spacing: f64) -> Daylight {
    let centre = spring.truncate();
    let downhill = |p: DVec2| {
        let g = ground.gradient(p);
        if g.length() > 1e-12 { -g.normalize() } else { DVec2::X }
    };
    let rise = Daylight::Mouth(Mouth { point: ground.on_ground(centre), direction: downhill(centre) });
    let above = ground.height(centre) - spring.z;
    if above <= AT_SURFACE {
        return rise;
    }
    let mut inner = 0.0;
    let mut radius = spacing.min(above);
    while inner < above {
        let count = ((std::f64::consts::TAU * radius / spacing).ceil() as usize).clamp(16, 720);
        let directions =
            (0..count).map(|k| DVec2::from_angle(k as f64 * std::f64::consts::TAU / count as f64));
        let (side, edge) = nearest_side(ground, centre);
        if side <= radius {
            return Daylight::Side(edge.extend(spring.z));
        }
        let hit = directions
            .map(|d| (ground.height(centre + d * radius), d))
            .filter(|(h, _)| *h <= spring.z)
            .min_by(|a, b| a.0.total_cmp(&b.0));
        if let Some((_, d)) = hit {
            // The wall lies between the last two rings: bisect for the ground at the spring's level.
            let (mut a, mut b) = (inner, radius);
            for _ in 0..40 {
                let mid = 0.5 * (a + b);
                if ground.height(centre + d * mid) <= spring.z { b = mid } else { a = mid }
            }
            let p = centre + d * b;
            return Daylight::Mouth(Mouth { point: p.extend(spring.z), direction: d });
        }
        inner = radius;
        radius = (radius + spacing).min(above.max(radius + 1e-9));
    }
    rise
}

/// Distance from `p` to the footprint's nearest side, and the nearest point of that side.
fn nearest_side(ground: &Ground, p: DVec2) -> (f64, DVec2) {
    let (lo, hi) = (ground.domain.min, ground.domain.max);
    [
        (p.x - lo[0], DVec2::new(lo[0], p.y)),
        (hi[0] - p.x, DVec2::new(hi[0], p.y)),
        (p.y - lo[1], DVec2::new(p.x, lo[1])),
        (hi[1] - p.y, DVec2::new(p.x, hi[1])),
    ]
    .into_iter()
    .fold((f64::INFINITY, p), |best, c| if c.0 < best.0 { c } else { best })
}

#[cfg(test)]
mod tests {
    use karst_geology::{Domain, Terrain};

    use super::*;

    #[test]
    fn a_spring_inside_a_cliff_comes_out_on_its_face() {
        // A plane falling east at 2 m per metre: at 20 m elevation the ground is at x = 40.
        let terrain = Terrain::Plane { elevation: 100.0, origin: [0.0, 0.0], gradient: [-2.0, 0.0] };
        let ground = Ground {
            terrain: &terrain,
            domain: Domain { min: [0.0; 3], max: [100.0, 100.0, 200.0] },
            probe: 0.5,
        };
        let Daylight::Mouth(m) = find(&ground, DVec3::new(30.0, 50.0, 20.0), 1.0) else { panic!() };
        assert!((m.point.x - 40.0).abs() < 1e-6 && (m.point.y - 50.0).abs() < 1e-9, "{m:?}");
        assert_eq!(m.point.z, 20.0);
        assert!(m.direction.x > 0.99);
        // Nearer the domain's south side (2 m) than any ground: it leaves the domain there.
        assert_eq!(
            find(&ground, DVec3::new(20.0, 2.0, 20.0), 1.0),
            Daylight::Side(DVec3::new(20.0, 0.0, 20.0))
        );
    }

    #[test]
    fn a_shallow_spring_under_a_flat_rises_to_the_ground() {
        let terrain = Terrain::Plane { elevation: 100.0, origin: [0.0, 0.0], gradient: [0.0, 0.0] };
        let ground = Ground {
            terrain: &terrain,
            domain: Domain { min: [0.0; 3], max: [100.0, 100.0, 200.0] },
            probe: 0.5,
        };
        let Daylight::Mouth(m) = find(&ground, DVec3::new(50.0, 50.0, 97.0), 1.0) else { panic!() };
        assert_eq!(m.point, DVec3::new(50.0, 50.0, 100.0));
    }
}
