//! The sampling stage's work estimate, made before anything large is allocated: the samples
//! expected from the radius field, the field's own nodes, the background grid's cells and
//! its neighbour offsets, each at its measured cost in bytes (BENCHMARKS.md: about 60 bytes
//! per sample at the peak on 1M samples, counted here at 100 with the transient buffers).
//!
//! The samples are counted on a coarse tabulation of the very radius field the sampler uses
//! (32k nodes, in the bedrock only), plus the thin layers of `surface_radius` around the
//! water tables, horizons and faults, which a coarse grid steps over: per surface, its area
//! times the integral of the extra density across the layer.

use glam::DVec3;

use karst_geology::Geometry;
use karst_scene::budget::{Cheaper, Estimate, OverBudget};
use karst_scene::params::SamplingParams;

use crate::spacing::{PACKING, SpacingField, unit_scale};
use crate::view::SamplingView;

/// Bytes per sample at the peak of the stage.
const BYTES_PER_SAMPLE: f64 = 100.0;
/// Bytes per node of the radius field (its values, and the parallel collection's copy).
const BYTES_PER_NODE: f64 = 8.0;
/// Bytes per background cell (list head, region bits, corner flags).
const BYTES_PER_CELL: f64 = 7.0;
/// Bytes per neighbour offset (as coordinates and as an index delta).
const BYTES_PER_OFFSET: f64 = 40.0;
/// Nodes of the coarse field the samples are counted on.
const COARSE_NODES: f64 = 32768.0;

/// What sampling the scene would allocate.
#[derive(Debug, Clone, Copy)]
struct Work {
    volume_samples: f64,
    surface_samples: f64,
    field_nodes: f64,
    cells: f64,
    offsets: f64,
}

impl Work {
    fn of(view: &SamplingView) -> Work {
        let s = view.sampling;
        let scale = unit_scale(view.sampling, view.domain);
        let radius = s.radius_metres(view.domain, view.terrain);
        let size = view.domain.size();
        let cells = (size / radius).ceil().max(DVec3::ONE).element_product();
        let largest = s
            .surface_radius
            .into_iter()
            .chain(view.geology.layers.iter().filter_map(|l| l.radius))
            .fold(radius / scale, f64::max)
            * scale;
        let reach = (largest / radius).ceil();
        let bedrock = |p: DVec3| p.z < view.terrain.height(p.x, p.y) && !view.geology.in_no_karst(p);
        let volume_samples = if cells.is_finite() && reach.is_finite() {
            SpacingField::tabulate(view, COARSE_NODES).expected_samples(bedrock)
        } else {
            f64::INFINITY
        };
        Work {
            volume_samples,
            surface_samples: surface_layers(view),
            field_nodes: SpacingField::nodes_for(view),
            cells,
            offsets: (2.0 * reach + 1.0).powi(3),
        }
    }

    fn samples(&self) -> f64 {
        self.volume_samples + self.surface_samples
    }

    fn bytes(&self) -> f64 {
        self.samples() * BYTES_PER_SAMPLE
            + self.field_nodes * BYTES_PER_NODE
            + self.cells * BYTES_PER_CELL
            + self.offsets * BYTES_PER_OFFSET
    }
}

/// The extra samples of the thin layers around the surfaces: per surface, its area in the
/// domain times ∫ PACKING (1/r(d)³ − 1/r_volume³) dd across the layer.
fn surface_layers(view: &SamplingView) -> f64 {
    let s = view.sampling;
    let scale = unit_scale(view.sampling, view.domain);
    let radius = s.radius_metres(view.domain, view.terrain);
    let Some(surface_radius) = s.surface_radius.map(|r| r * scale).filter(|r| *r < radius) else {
        return 0.0;
    };
    let distance = s.surface_distance.map_or(2.0 * radius, |d| d * scale);
    // Midpoint rule over the layer's half-thickness: r grows by a smoothstep from the surface.
    const STEPS: usize = 64;
    let per_area: f64 = (0..STEPS)
        .map(|k| {
            let t = (k as f64 + 0.5) / STEPS as f64;
            let r = surface_radius + (radius - surface_radius) * t * t * (3.0 - 2.0 * t);
            PACKING * (r.powi(-3) - radius.powi(-3)) * distance / STEPS as f64
        })
        .sum::<f64>()
        * 2.0;
    let g = view.geology;
    let area: f64 = g
        .water_tables
        .iter()
        .chain(&g.horizons)
        .chain(&g.faults)
        .map(|s| surface_area(view, &s.geometry))
        .sum();
    per_area * area
}

/// Area of a surface within the domain (a TIN: its whole area).
fn surface_area(view: &SamplingView, geometry: &Geometry) -> f64 {
    let size = view.domain.size();
    match geometry {
        Geometry::Plane { dip, .. } if *dip < 89.0 => size.x * size.y / dip.to_radians().cos(),
        Geometry::Plane { .. } => size.x.hypot(size.y) * size.z,
        Geometry::Tin { mesh, .. } => mesh.area(),
    }
}

/// The scene field that drives the estimate, its value, and the estimate's bytes with another
/// value of it, everything else unchanged.
type Driver = (String, f64, Estimator);

/// The estimate's bytes with the driving field set to another value.
type Estimator = Box<dyn Fn(&SamplingView, f64) -> f64>;

/// The field to name: the smallest of `radius`, `surface_radius` and the layers' radii (the
/// density of samples grows as the inverse cube of the radius).
fn driver(view: &SamplingView) -> Driver {
    let s = view.sampling;
    let with_sampling = |set: fn(&mut SamplingParams, f64)| -> Estimator {
        Box::new(move |view, v| {
            let mut sampling = view.sampling.clone();
            set(&mut sampling, v);
            Work::of(&SamplingView { sampling: &sampling, ..*view }).bytes()
        })
    };
    let radius = s.radius_in_units(view.domain, view.terrain);
    let mut best: Driver = ("sampling.radius".into(), radius, with_sampling(|s, v| s.radius = Some(v)));
    if let Some(r) = s.surface_radius.filter(|r| *r < best.1) {
        best = ("sampling.surface_radius".into(), r, with_sampling(|s, v| s.surface_radius = Some(v)));
    }
    for (i, layer) in view.geology.layers.iter().enumerate() {
        if let Some(r) = layer.radius.filter(|r| *r < best.1) {
            best = (
                format!("geology.layers[{i}].radius"),
                r,
                Box::new(move |view, v| {
                    let mut geology = view.geology.clone();
                    geology.layers[i].radius = Some(v);
                    Work::of(&SamplingView { geology: &geology, ..*view }).bytes()
                }),
            );
        }
    }
    best
}

/// Refuses a scene whose sampling would exceed the memory budget.
pub fn check(view: &SamplingView) -> Result<(), OverBudget> {
    let work = Work::of(view);
    let (field, value, bytes_at) = driver(view);
    let estimate = Estimate {
        what: format!(
            "{:.2e} samples and {:.2e} grid cells",
            work.samples(),
            work.cells.max(work.field_nodes)
        ),
        bytes: work.bytes(),
        field,
        value,
    };
    view.budget.check(estimate, Cheaper::Larger, false, |v| bytes_at(view, v))
}
