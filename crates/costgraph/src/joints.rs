//! The joint sets the cost model assumes when the scene gives no fracture family
//! (`costgraph.assumed_joints`, docs/costgraph.md "Assumed joints").
//!
//! Cave passages follow joints and bedding far more often than they cut across them (Palmer
//! 1991: most passages of branchwork caves are guided by a few fracture sets); in flat-lying
//! and gently folded carbonates the systematic joints come as two near-vertical sets about
//! 90° apart. A scene without `[[geology.fractures]]` says nothing about them, and with no
//! preferred direction the least-cost routes spread their azimuths almost uniformly
//! (orientation entropy 0.997–1.000, above every real cave's). So the cost model assumes that
//! orthogonal pair, and orients it as a geologist without field data would, from the terrain's
//! lineaments: valleys and scarps of karst terrains follow the same fractures the caves do,
//! and the axes of the terrain's gradient structure tensor (the dominant slope direction and
//! the one across it) are the directions those lineaments take. A flat terrain has no axis:
//! the pair is then north–south and east–west.

use karst_geology::{Domain, FractureFamily, Terrain};

/// Angular tolerance of an assumed set, degrees (the scene's fracture families default).
pub const ASSUMED_TOLERANCE: f64 = 10.0;

/// Terrain samples per axis for the structure tensor.
const SAMPLES: usize = 64;

/// The two vertical joint sets assumed on `terrain` over `domain`: strikes along and across
/// its lineaments ([`lineament_azimuth`]), each at [`ASSUMED_TOLERANCE`] and weight 1.
pub fn assumed(domain: &Domain, terrain: &Terrain) -> [FractureFamily; 2] {
    let along = lineament_azimuth(domain, terrain);
    let family = |name: &str, azimuth: f64| FractureFamily {
        name: name.into(),
        azimuth,
        dip: 90.0,
        tolerance: ASSUMED_TOLERANCE,
        weight: 1.0,
    };
    [family("assumed-along", along), family("assumed-across", (along + 90.0) % 180.0)]
}

/// The axial azimuth, degrees in [0, 180) clockwise from north rounded to the degree, of the
/// terrain's dominant slope direction: the major axis of the structure tensor Σ ∇h ∇hᵀ over a
/// [`SAMPLES`]² lattice of the domain (central differences). 0 when the tensor is isotropic
/// (a flat terrain). Rounded so that the assumed sets, recorded in the run, read as a
/// geologist would write them and do not move with the last bits of a terrain's heights.
pub fn lineament_azimuth(domain: &Domain, terrain: &Terrain) -> f64 {
    let (min, size) = (domain.min, [domain.max[0] - domain.min[0], domain.max[1] - domain.min[1]]);
    let (dx, dy) = (size[0] / SAMPLES as f64, size[1] / SAMPLES as f64);
    let (mut xx, mut xy, mut yy) = (0.0, 0.0, 0.0);
    for j in 0..SAMPLES {
        for i in 0..SAMPLES {
            let (x, y) = (min[0] + (i as f64 + 0.5) * dx, min[1] + (j as f64 + 0.5) * dy);
            let gx = (terrain.height(x + dx / 2.0, y) - terrain.height(x - dx / 2.0, y)) / dx;
            let gy = (terrain.height(x, y + dy / 2.0) - terrain.height(x, y - dy / 2.0)) / dy;
            (xx, xy, yy) = (xx + gx * gx, xy + gx * gy, yy + gy * gy);
        }
    }
    let anisotropy = (xx - yy).hypot(2.0 * xy);
    // Isotropic (or no slope at all, or a NaN height): no axis.
    if anisotropy.is_nan() || anisotropy <= 1e-9 * (xx + yy) {
        return 0.0;
    }
    // Angle of the major axis from east, counter-clockwise; the azimuth is from north, clockwise.
    let from_east = 0.5 * (2.0 * xy).atan2(xx - yy);
    let azimuth = (90.0 - from_east.to_degrees()).rem_euclid(180.0).round();
    if azimuth >= 180.0 { 0.0 } else { azimuth }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn plane(gradient: [f64; 2]) -> Terrain {
        Terrain::Plane { elevation: 100.0, origin: [0.0, 0.0], gradient }
    }

    const DOMAIN: Domain = Domain { min: [0.0, 0.0, 0.0], max: [1000.0, 800.0, 200.0] };

    #[test]
    fn the_sets_follow_the_slope_and_cross_it() {
        // Slope down to the east: dip direction E–W, azimuth 90.
        assert_eq!(lineament_azimuth(&DOMAIN, &plane([-0.1, 0.0])), 90.0);
        // Slope towards the north: azimuth 0.
        assert_eq!(lineament_azimuth(&DOMAIN, &plane([0.0, 0.05])), 0.0);
        // Slope along the north-east diagonal: 45.
        assert_eq!(lineament_azimuth(&DOMAIN, &plane([0.1, 0.1])), 45.0);
        // Along north-west: 135.
        assert_eq!(lineament_azimuth(&DOMAIN, &plane([-0.1, 0.1])), 135.0);
        let [along, across] = assumed(&DOMAIN, &plane([0.1, 0.1]));
        assert_eq!((along.azimuth, across.azimuth), (45.0, 135.0));
        assert!(along.normal().dot(across.normal()).abs() < 1e-12);
    }

    #[test]
    fn a_flat_terrain_gives_north_and_east() {
        let [along, across] = assumed(&DOMAIN, &plane([0.0, 0.0]));
        assert_eq!((along.azimuth, across.azimuth), (0.0, 90.0));
    }
}
