//! The ensemble probability of every conduit segment, when the run folder also holds the
//! outputs of `karstgen ensemble SCENE --out RUN` (docs/ensembles.md): `probability/grid.json`
//! places the grid, `probability/z-NNN.exr` holds, per cell, the fraction of realizations with
//! a conduit there.
//!
//! A segment's probability is the largest over the cells its axis passes through, sampled every
//! quarter cell as the ensemble itself marks a conduit's cells; so when the ensemble's seeds
//! include the scene's own (the default `--n` does), each segment of the run gets at least 1/n.

use std::path::{Path, PathBuf};

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

/// Most cells a probability grid may have (4 bytes each: 1 GiB).
pub const MAX_CELLS: usize = 1 << 28;
/// Most probes along the network (every quarter cell of every segment): the work of the
/// colouring, bounded whatever `cell` says.
pub const MAX_PROBES: f64 = 1e8;

/// A file of the ensemble folder that cannot be used, and why (a field of grid.json and its value
/// where one is wrong).
#[derive(Debug, thiserror::Error)]
#[error("{}: {problem}", file.display())]
pub struct EnsembleError {
    pub file: PathBuf,
    pub problem: String,
}

impl EnsembleError {
    fn new(file: &Path, problem: impl std::fmt::Display) -> Self {
        EnsembleError { file: file.to_path_buf(), problem: problem.to_string() }
    }
}

/// The ensemble colouring of `skeleton` from `run_dir/probability/`, None when the folder has no
/// ensemble, an error message when it has a broken one.
pub fn load(run_dir: &Path, skeleton: &Skeleton) -> Option<Result<EnsembleView, EnsembleError>> {
    let folder = run_dir.join("probability");
    let placement = folder.join("grid.json");
    if !placement.is_file() {
        return None;
    }
    Some(read_grid(&folder, skeleton).map(|(p, values)| {
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

/// The placement and every cell's probability (x fastest, then y, then z), once the placement
/// is checked: a finite corner, a cell > 0 fine enough for at most [`MAX_PROBES`] probes along
/// `skeleton`, at most [`MAX_CELLS`] cells, at least one realization.
fn read_grid(folder: &Path, skeleton: &Skeleton) -> Result<(Placement, Vec<f32>), EnsembleError> {
    let path = folder.join("grid.json");
    let text = karst_artifact::files::read_regular_text(&path, karst_artifact::files::MAX_SCENE_BYTES)
        .map_err(|e| EnsembleError::new(&path, e))?;
    let p: Placement = serde_json::from_str(&text).map_err(|e| EnsembleError::new(&path, e))?;
    check_placement(&p, skeleton).map_err(|problem| EnsembleError::new(&path, problem))?;
    let [nx, ny, nz] = p.dims;
    let mut values = Vec::with_capacity(nx * ny * nz);
    for z in 0..nz {
        let slice = folder.join(format!("z-{z:03}.exr"));
        karst_artifact::files::open_regular(&slice, karst_artifact::files::MAX_DATA_BYTES)
            .map_err(|e| EnsembleError::new(&slice, e))?;
        let image = exr::prelude::read_first_flat_layer_from_file(&slice)
            .map_err(|e| EnsembleError::new(&slice, e))?;
        let layer = &image.layer_data;
        let channel = layer
            .channel_data
            .list
            .iter()
            .find(|c| c.name.to_string() == "P")
            .ok_or_else(|| EnsembleError::new(&slice, "no channel P"))?;
        if (layer.size.width(), layer.size.height()) != (nx, ny) {
            let (width, height) = (layer.size.width(), layer.size.height());
            return Err(EnsembleError::new(
                &slice,
                format!("{width}×{height} pixels, grid.json says {nx}×{ny}"),
            ));
        }
        values.extend(channel.sample_data.values_as_f32());
    }
    if values.len() != nx * ny * nz {
        return Err(EnsembleError::new(folder, format!("{} values for {nx}×{ny}×{nz} cells", values.len())));
    }
    Ok((p, values))
}

/// A field of grid.json that cannot place the ensemble's grid, with its value.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
enum PlacementError {
    #[error("min[{axis}] = {value} is not a finite coordinate")]
    Min { axis: usize, value: f64 },
    #[error("cell = {0} is not a finite length > 0")]
    Cell(f64),
    #[error("realizations = 0: an ensemble has at least one")]
    NoRealization,
    #[error("dims = {dims:?} is not a grid of 1 to {MAX_CELLS} cells")]
    Dims { dims: [usize; 3] },
    #[error(
        "cell = {cell} m takes {probes:.1e} probes along the network's {length:.0} m; at most {MAX_PROBES:e}: \
         cell ≥ {:.3e} m would fit",
        4.0 * length / MAX_PROBES
    )]
    TooFine { cell: String, probes: f64, length: f64 },
}

/// What grid.json's fields must be, naming the field and its value when they are not.
fn check_placement(p: &Placement, skeleton: &Skeleton) -> Result<(), PlacementError> {
    if let Some(axis) =
        (0..3).find(|&a| p.min[a].is_nan() || p.min[a].abs() > karst_artifact::check::MAX_COORDINATE)
    {
        return Err(PlacementError::Min { axis, value: p.min[axis] });
    }
    if !(p.cell.is_finite() && p.cell > 0.0) {
        return Err(PlacementError::Cell(p.cell));
    }
    if p.realizations == 0 {
        return Err(PlacementError::NoRealization);
    }
    let cells = p.dims.iter().try_fold(1usize, |n, &d| n.checked_mul(d)).filter(|&n| n <= MAX_CELLS);
    if p.dims.contains(&0) || cells.is_none() {
        return Err(PlacementError::Dims { dims: p.dims });
    }
    let length: f64 = skeleton
        .conduits
        .iter()
        .flat_map(|c| c.nodes.windows(2))
        .map(|w| distance(skeleton.nodes[w[0] as usize].position, skeleton.nodes[w[1] as usize].position))
        .sum();
    let probes = length / (p.cell / 4.0);
    if probes > MAX_PROBES {
        let cell = if (1e-3..1e6).contains(&p.cell) { p.cell.to_string() } else { format!("{:e}", p.cell) };
        return Err(PlacementError::TooFine { cell, probes, length });
    }
    Ok(())
}

fn distance(a: [f64; 3], b: [f64; 3]) -> f64 {
    (0..3).map(|i| (b[i] - a[i]).powi(2)).sum::<f64>().sqrt()
}

/// The largest probability over the cells the segment a→b passes through.
fn segment_probability(p: &Placement, values: &[f32], skeleton: &Skeleton, a: u32, b: u32) -> f32 {
    let (pa, pb) = (skeleton.nodes[a as usize].position, skeleton.nodes[b as usize].position);
    let length = distance(pa, pb);
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

#[cfg(test)]
mod tests {
    use super::*;
    use karst_testkit::{root, scratch};

    /// The error for a grid.json of `text` beside the tiny golden skeleton.
    fn problem(text: &str) -> String {
        let (_, skeleton) =
            karst_artifact::read_artifact::<Skeleton>(&root().join("fixtures/golden/tiny/skeleton.json"))
                .unwrap();
        let run = scratch("view-ensemble-grid");
        std::fs::create_dir_all(run.join("probability")).unwrap();
        std::fs::write(run.join("probability/grid.json"), text).unwrap();
        let message = load(&run, &skeleton).expect("a grid is there").expect_err("a bad grid").to_string();
        std::fs::remove_dir_all(&run).unwrap();
        message
    }

    #[test]
    fn bad_placements_name_the_field_and_value() {
        let grid = |min: &str, cell: &str, dims: &str, n: &str| {
            format!(r#"{{"min":{min},"cell":{cell},"dims":{dims},"realizations":{n}}}"#)
        };
        let ok = ("[0,0,0]", "10", "[4,4,4]");
        let huge = problem(&grid(ok.0, ok.1, "[100000,100000,100000]", "3"));
        assert!(huge.contains("dims = [100000, 100000, 100000]"), "{huge}");
        let overflow = problem(&grid(ok.0, ok.1, "[18446744073709551615,2,1]", "3"));
        assert!(overflow.contains("dims"), "{overflow}");
        let fine = problem(&grid(ok.0, "1e-300", ok.2, "3"));
        assert!(fine.contains("cell = 1e-300 m takes") && fine.contains("would fit"), "{fine}");
        assert!(problem(&grid(ok.0, "-1", ok.2, "3")).contains("cell = -1"));
        assert!(problem(&grid("[0,1e300,0]", ok.1, ok.2, "3")).contains("min[1] = "));
        assert!(problem(&grid(ok.0, ok.1, ok.2, "0")).contains("realizations = 0"));
        assert!(
            problem(&grid(ok.0, ok.1, ok.2, "3")).contains("z-000.exr"),
            "slices are read once the grid is sane"
        );
    }
}
