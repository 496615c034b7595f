//! The cell the cave and the water are meshed at, chosen from the karst's thinnest leaf; read
//! by the mesher's build and by its work estimate before any cell is evaluated.

use karst_sdf::SdfModel;

/// The cell of the cave alone and the water: `requested` when positive, else the half-thickness
/// of the thinnest karst leaf (capsule or sphere radius, half the smaller side of a sweep's
/// section, chamber radius), at most `cell_size` and at least `cell_size` / [`CAVE_REFINE`] or
/// [`SMALLEST_PASSAGE`],
/// whichever is smaller. Every point of space is within √3/2 cells of a lattice point, so a
/// conduit at least a cell thick always holds lattice points: it cannot fall between them, and a
/// pinch of a passage profile never closes the mesh.
pub fn cave_cell(model: &SdfModel, cell_size: f64, requested: f64) -> f64 {
    if requested > 0.0 {
        return requested;
    }
    let section = |s: &karst_sdf::SectionSpec| (s.shape.radius * s.shape.ratio.min(1.0)) as f64;
    let thinnest = model
        .capsules
        .iter()
        .map(|c| c.radius)
        .chain(model.spheres.iter().flat_map(|g| g.spheres.iter().map(|s| s[3] as f64)))
        .chain(model.sweeps.iter().flat_map(|s| [section(&s.sweep.start), section(&s.sweep.end)]))
        .chain(model.chambers.iter().map(|c| c.radius as f64))
        .filter(|r| *r > 0.0)
        .fold(f64::INFINITY, f64::min);
    let finest = (cell_size / CAVE_REFINE).min(SMALLEST_PASSAGE);
    thinnest.clamp(finest, cell_size)
}

/// The automatic cave cell is at most this many times finer than the terrain's (the cost grows
/// as its square).
pub const CAVE_REFINE: f64 = 8.0;

/// The smallest half-width and half-height of a passage profile, metres (the skeleton's
/// `passages::MIN_HALF_WIDTH`, docs/skeleton.md "Passages"): the automatic cave cell is never
/// coarser than it when a leaf is that thin, whatever `cell_size`, so that a pinch stays open.
pub const SMALLEST_PASSAGE: f64 = 0.5;
