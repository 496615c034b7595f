//! The ensemble probability of every conduit segment, when the run folder also holds the
//! outputs of `karstgen ensemble SCENE --out RUN` (docs/ensembles.md): `probability/grid.json`
//! places the grid, `probability/z-NNN.exr` holds, per cell, the fraction of realizations with
//! a conduit there.
//!
//! A segment's probability is the largest over the cells its axis passes through, sampled every
//! quarter cell as the ensemble itself marks a conduit's cells; so when the ensemble's seeds
//! include the scene's own (the default `--n` does), each segment of the run gets at least 1/n.

use std::path::Path;

use serde::{Deserialize, Serialize};

use karst_skeleton::Skeleton;

/// `probability/grid.json`.
#[derive(Debug, Clone, Deserialize)]
struct Placement {
    min: [f64; 3],
    cell: f64,
    dims: [usize; 3],
    realizations: usize,
}

/// The probability of every segment, in run.json.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct EnsembleView {
    pub realizations: usize,
    /// Grid cell, metres.
    pub cell: f64,
    /// Per conduit, one probability per segment.
    pub segments: Vec<Vec<f32>>,
}

/// The ensemble colouring of `skeleton` from `run_dir/probability/`, None when the folder has no
/// ensemble, an error message when it has a broken one.
pub fn load(run_dir: &Path, skeleton: &Skeleton) -> Option<Result<EnsembleView, String>> {
    let folder = run_dir.join("probability");
    let placement = folder.join("grid.json");
    if !placement.is_file() {
        return None;
    }
    Some(read_grid(&folder).map(|(p, values)| {
        EnsembleView {
            realizations: p.realizations,
            cell: p.cell,
            segments: skeleton
                .conduits
                .iter()
                .map(|c| {
                    c.nodes
                        .windows(2)
                        .map(|w| segment_probability(&p, &values, skeleton, w[0], w[1]))
                        .collect()
                })
                .collect(),
        }
    }))
}

/// The placement and every cell's probability (x fastest, then y, then z).
fn read_grid(folder: &Path) -> Result<(Placement, Vec<f32>), String> {
    let path = folder.join("grid.json");
    let text = std::fs::read_to_string(&path).map_err(|e| format!("{}: {e}", path.display()))?;
    let p: Placement = serde_json::from_str(&text).map_err(|e| format!("{}: {e}", path.display()))?;
    let [nx, ny, nz] = p.dims;
    if !(p.cell.is_finite() && p.cell > 0.0) || nx * ny * nz == 0 {
        return Err(format!("{}: cell {} and dims {:?} make no grid", path.display(), p.cell, p.dims));
    }
    let mut values = Vec::with_capacity(nx * ny * nz);
    for z in 0..nz {
        let slice = folder.join(format!("z-{z:03}.exr"));
        let image = exr::prelude::read_first_flat_layer_from_file(&slice)
            .map_err(|e| format!("{}: {e}", slice.display()))?;
        let layer = &image.layer_data;
        let channel = layer
            .channel_data
            .list
            .iter()
            .find(|c| c.name.to_string() == "P")
            .ok_or_else(|| format!("{}: no channel P", slice.display()))?;
        if (layer.size.width(), layer.size.height()) != (nx, ny) {
            return Err(format!(
                "{}: {}×{} pixels, grid.json says {nx}×{ny}",
                slice.display(),
                layer.size.width(),
                layer.size.height()
            ));
        }
        values.extend(channel.sample_data.values_as_f32());
    }
    Ok((p, values))
}

/// The largest probability over the cells the segment a→b passes through.
fn segment_probability(p: &Placement, values: &[f32], skeleton: &Skeleton, a: u32, b: u32) -> f32 {
    let (pa, pb) = (skeleton.nodes[a as usize].position, skeleton.nodes[b as usize].position);
    let length = (0..3).map(|i| (pb[i] - pa[i]).powi(2)).sum::<f64>().sqrt();
    let steps = (length / (p.cell / 4.0)).ceil().max(1.0) as usize;
    (0..=steps)
        .filter_map(|s| {
            let t = s as f64 / steps as f64;
            cell_index(p, [0, 1, 2].map(|i| pa[i] + (pb[i] - pa[i]) * t))
        })
        .map(|c| values[c])
        .fold(0.0, f32::max)
}

fn cell_index(p: &Placement, point: [f64; 3]) -> Option<usize> {
    let mut ijk = [0usize; 3];
    for a in 0..3 {
        let t = ((point[a] - p.min[a]) / p.cell).floor();
        if !(t >= 0.0 && t < p.dims[a] as f64) {
            return None;
        }
        ijk[a] = t as usize;
    }
    Some((ijk[2] * p.dims[1] + ijk[1]) * p.dims[0] + ijk[0])
}
