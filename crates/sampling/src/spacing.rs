//! The sampling radius field r(p), tabulated on a regular grid and interpolated trilinearly.
//!
//! r is small on and near the horizons, water tables and faults (so that conduits can follow
//! them closely), takes each layer's radius in its layer, and shrinks in karstifiable rock
//! (Paris et al. 2021 §4.1 adaptive sampling; KarstNSim §1.1 variable density):
//! r_vol(p) = r_layer(p) · (1 + (potential_factor − 1)·P(p)),
//! r(p) = r_surface + (r_vol(p) − r_surface)·g(d(p)/surface_distance), g the smoothstep and d
//! the distance to the nearest surface. The tabulated field is the one the sampler honours and
//! the artifact records, so spacing can be checked exactly afterwards.

use glam::DVec3;
use rayon::prelude::*;
use serde::{Deserialize, Serialize};

use karst_geology::{Domain, Geometry, Surface};
use karst_scene::params::{RadiusUnit, SamplingParams};

use crate::view::SamplingView;

/// The field uses at most this many nodes per expected sample at the base radius (and at
/// least 32³ nodes): it is smooth, so a coarser table loses nothing the sampler needs.
const NODES_PER_SAMPLE: f64 = 2.0;
/// The fewest nodes of a field.
const MIN_NODES: f64 = 32768.0;
/// Samples per cubic radius of a maximal Poisson-disk set (random close packing of spheres of
/// diameter r).
pub const PACKING: f64 = 0.725;

/// A surface as the radius field measures distances to it.
enum Near<'a> {
    /// Unit normal and a point of a plane.
    Plane(DVec3, DVec3),
    Other(&'a Surface),
}

/// A radius field on the nodes origin + (i, j, k)·cell.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct SpacingField {
    pub origin: [f64; 3],
    pub cell: f64,
    pub size: [u32; 3],
    /// Radii, metres, x fastest.
    pub values: Vec<f32>,
}

/// Scale of `[sampling]` lengths: 1 for metres, the largest domain extent for "domain".
pub fn unit_scale(sampling: &SamplingParams, domain: &Domain) -> f64 {
    match sampling.units {
        RadiusUnit::Metres => 1.0,
        RadiusUnit::Domain => domain.size().max_element(),
    }
}

impl SpacingField {
    /// Tabulates the scene's radius field.
    pub fn of_view(view: &SamplingView) -> SpacingField {
        SpacingField::tabulate(view, SpacingField::nodes_for(view))
    }

    /// Nodes of the scene's field: [`NODES_PER_SAMPLE`] per expected sample at the base radius,
    /// at least 32³.
    pub fn nodes_for(view: &SamplingView) -> f64 {
        let radius = view.sampling.radius_metres(view.domain, view.terrain);
        let volume = view.domain.size().element_product();
        (NODES_PER_SAMPLE * PACKING * volume / radius.powi(3)).max(MIN_NODES)
    }

    /// The scene's radius field on about `nodes` nodes (cells no smaller than the smallest
    /// radius); the work estimate tabulates a coarse one.
    pub fn tabulate(view: &SamplingView, nodes: f64) -> SpacingField {
        let s = view.sampling;
        let scale = unit_scale(view.sampling, view.domain);
        let radius = s.radius_metres(view.domain, view.terrain);
        let surface_radius = s.surface_radius.map_or(radius, |r| r * scale);
        let surface_distance = s.surface_distance.map_or(2.0 * radius, |d| d * scale);
        let layer_min = view.geology.layer_radii().fold(f64::INFINITY, f64::min) * scale;
        let smallest = radius.min(surface_radius).min(layer_min).min(radius * s.potential_factor);
        let size = view.domain.size();
        let volume = size.element_product();
        let cell = smallest.max((volume / nodes).cbrt());
        let n = (size / cell).ceil().as_uvec3() + 1;
        let origin = view.domain.min();
        // Planes keep their normal (a sin/cos per call of `Surface::normal`) and a point:
        // the same arithmetic as `Surface::distance_within`, once per surface.
        let surfaces: Vec<Near> = view
            .geology
            .water_tables
            .iter()
            .chain(&view.geology.horizons)
            .chain(&view.geology.faults)
            .map(|s| match &s.geometry {
                Geometry::Plane { elevation, origin, .. } => {
                    Near::Plane(s.normal(), DVec3::new(origin[0], origin[1], *elevation))
                }
                Geometry::Tin { .. } => Near::Other(s),
            })
            .collect();
        let at = |p: DVec3| -> f32 {
            let layer = view.geology.layer_at(p).and_then(|l| l.radius).map_or(radius, |r| r * scale);
            let volume = layer * (1.0 + (s.potential_factor - 1.0) * view.geology.potential(p));
            let d = surfaces.iter().fold(surface_distance, |d, w| match w {
                Near::Plane(n, o) => n.dot(p - *o).abs().min(d),
                Near::Other(s) => s.distance_within(p, d),
            });
            let t = (d / surface_distance).clamp(0.0, 1.0);
            (surface_radius + (volume - surface_radius) * t * t * (3.0 - 2.0 * t)) as f32
        };
        let values: Vec<f32> = (0..n.z)
            .into_par_iter()
            .flat_map_iter(|k| {
                (0..n.y).flat_map(move |j| {
                    (0..n.x).map(move |i| at(origin + DVec3::new(i as f64, j as f64, k as f64) * cell))
                })
            })
            .collect();
        SpacingField { origin: origin.to_array(), cell, size: [n.x, n.y, n.z], values }
    }

    /// Trilinear radius at `p`, clamped to the grid.
    pub fn at(&self, p: DVec3) -> f64 {
        let mut base = [0usize; 3];
        let mut frac = [0.0f64; 3];
        for a in 0..3 {
            let n = self.size[a] as usize;
            let t = ((p[a] - self.origin[a]) / self.cell).clamp(0.0, (n - 1) as f64);
            base[a] = (t as usize).min(n.saturating_sub(2));
            frac[a] = (t - base[a] as f64).min(1.0);
        }
        let [nx, ny] = [self.size[0] as usize, self.size[1] as usize];
        let step = [1usize, nx, nx * ny];
        let first = base[0] + nx * (base[1] + ny * base[2]);
        let mut sum = 0.0;
        for corner in 0..8usize {
            let mut w = 1.0;
            let mut idx = first;
            for a in 0..3 {
                if (corner >> a) & 1 == 1 {
                    w *= frac[a];
                    if self.size[a] > 1 {
                        idx += step[a];
                    }
                } else {
                    w *= 1.0 - frac[a];
                }
            }
            if w != 0.0 {
                sum += w * self.values[idx] as f64;
            }
        }
        sum
    }

    /// The largest tabulated radius.
    pub fn max(&self) -> f64 {
        self.values.iter().copied().fold(0.0, f32::max) as f64
    }

    /// The smallest node value of the cells around the box lo–hi: a lower bound of the field
    /// over the box.
    pub fn min_in(&self, lo: DVec3, hi: DVec3) -> f64 {
        let range = |a: usize| {
            let n = self.size[a] as usize;
            let i = (((lo[a] - self.origin[a]) / self.cell).floor().max(0.0) as usize).min(n - 1);
            let j = (((hi[a] - self.origin[a]) / self.cell).ceil().max(0.0) as usize).min(n - 1);
            i..=j
        };
        let [nx, ny] = [self.size[0] as usize, self.size[1] as usize];
        let mut m = f32::INFINITY;
        for k in range(2) {
            for j in range(1) {
                for i in range(0) {
                    m = m.min(self.values[(k * ny + j) * nx + i]);
                }
            }
        }
        m as f64
    }

    /// The smallest tabulated radius.
    pub fn min(&self) -> f64 {
        self.values.iter().copied().fold(f32::INFINITY, f32::min) as f64
    }

    /// Checks a decoded field: a grid of at least one node per axis holding one finite,
    /// positive radius per node.
    pub fn validate(&self) -> Result<(), karst_artifact::Invalid> {
        use karst_artifact::check::{self, MAX_COORDINATE, ensure};
        check::position(|| "radius_field.origin".into(), &self.origin)?;
        check::positive(|| "radius_field.cell".into(), self.cell, MAX_COORDINATE)?;
        let nodes = self.size.iter().try_fold(1usize, |n, &s| n.checked_mul(s as usize).filter(|_| s > 0));
        ensure(
            nodes == Some(self.values.len()),
            || "radius_field.values".into(),
            || format!("holds {} radii for a grid of {:?} nodes", self.values.len(), self.size),
        )?;
        match self.values.iter().position(|r| !(*r > 0.0 && r.is_finite())) {
            Some(i) => Err(karst_artifact::Invalid::new(
                format!("radius_field.values[{i}]"),
                format!("{} is not a finite radius > 0", self.values[i]),
            )),
            None => Ok(()),
        }
    }

    /// Expected number of samples of a maximal Poisson-disk set filling the nodes' cells that
    /// `region` keeps (random close packing of spheres of diameter r: about 0.725 / r³ per m³).
    pub fn expected_samples(&self, region: impl Fn(DVec3) -> bool) -> f64 {
        let [nx, ny, _] = self.size.map(|n| n as usize);
        let origin = DVec3::from_array(self.origin);
        self.values
            .iter()
            .enumerate()
            .filter(|(i, _)| {
                let at = DVec3::new((i % nx) as f64, (i / nx % ny) as f64, (i / (nx * ny)) as f64);
                region(origin + at * self.cell)
            })
            .map(|(_, r)| PACKING * self.cell.powi(3) / (*r as f64).powi(3))
            .sum()
    }
}
