//! `cargo xtask ensemble SCENE --n 50`: many realizations of one scene, differing only by seed.
//!
//! Realization k runs the scene with `seed = scene seed + k` (k = 0..n) through sampling,
//! costgraph and skeleton, in process and in parallel, and characterises its skeleton as the
//! metrics stage does. Written into the output folder:
//!
//! - `metrics.csv`: one row per realization (seed, every statistic of `metrics.json` under
//!   karstnet's key names, the vadose / phreatic lengths and the length per conduit type);
//! - `summary.csv`: min, mean and max of every column over the realizations (undefined values
//!   skipped and counted), and for karstnet's metrics the real-cave range and the fraction of
//!   realizations inside it;
//! - `probability/z-NNN.exr`: the conduit probability grid, one horizontal slice per file (one
//!   float channel `P`): the fraction of realizations with a conduit in each cell of `--cell`
//!   metres over the scene domain. A conduit occupies the cells its segments' axes pass through
//!   (sampled every quarter cell), whatever its radius;
//! - `probability/grid.json`: the grid's `min` corner, `cell` and `dims` (x, y, z) and the number
//!   of `realizations`, so that readers (the viewer) can place the slices;
//! - `probability-top.png`: the top view, the fraction of realizations with a conduit anywhere
//!   in each column of cells (north up).
//!
//! Every realization is deterministic and results are gathered in seed order, and the grid holds
//! integer counts, so the outputs are byte-identical whatever the number of threads.

use std::fmt::Write as _;
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicUsize, Ordering};

use rayon::prelude::*;

use karst_artifact::{Stage, StageError, read_artifact};
use karst_geology::Scene;
use karst_metrics::ranges::{CHARACTERIZE_KEYS, real_cave_ranges};
use karst_metrics::stage::{MetricsReport, report};
use karst_raster::{BLACK, Canvas, WHITE};
use karst_skeleton::Skeleton;

use crate::executor::{Executor, InProcess};

/// What to run.
#[derive(Debug, Clone)]
pub struct EnsembleArgs {
    pub scene: PathBuf,
    /// Number of realizations.
    pub n: usize,
    /// Edge of a probability-grid cell, metres.
    pub cell: f64,
    pub out: PathBuf,
}

/// One realization's results.
struct Realization {
    seed: u64,
    report: MetricsReport,
    /// Sorted indices of the grid cells its conduits pass through.
    cells: Vec<usize>,
}

/// Runs the ensemble and writes its outputs; returns a one-line summary.
pub fn run(args: &EnsembleArgs) -> Result<String, StageError> {
    if args.n == 0 || !(args.cell.is_finite() && args.cell > 0.0) {
        return Err(StageError::input(format!(
            "ensemble: --n must be ≥ 1 (got {}) and --cell > 0 m (got {})",
            args.n, args.cell
        )));
    }
    let text = std::fs::read_to_string(&args.scene)
        .map_err(|e| StageError::input(format!("{}: {e}", args.scene.display())))?;
    let scene = Scene::parse(&text, &args.scene)?;
    let grid = Grid::new(&scene, args.cell)?;
    static RUNS: AtomicUsize = AtomicUsize::new(0);
    let run_id = RUNS.fetch_add(1, Ordering::Relaxed);
    let scratch = std::env::temp_dir().join(format!("karstgen-ensemble-{}-{run_id}", std::process::id()));
    let bar = karst_artifact::progress::bar(args.n as u64, "ensemble");
    let realizations: Result<Vec<Realization>, StageError> = (0..args.n as u64)
        .into_par_iter()
        .map(|k| {
            let seed = scene.seed.checked_add(k).filter(|s| i64::try_from(*s).is_ok()).ok_or_else(|| {
                StageError::input(format!("{}: seed {} + {k} is too large", args.scene.display(), scene.seed))
            })?;
            let r = realize(&text, seed, &scratch.join(format!("seed-{seed}")), &grid);
            bar.inc(1);
            r
        })
        .collect();
    bar.finish_and_clear();
    let _ = std::fs::remove_dir_all(&scratch);
    let realizations = realizations?;
    write_outputs(args, &grid, &realizations)?;
    Ok(format!(
        "{} realizations of {} (seeds {}..={}) → {}",
        args.n,
        args.scene.display(),
        realizations[0].seed,
        realizations[realizations.len() - 1].seed,
        args.out.display()
    ))
}

/// Runs one seed in `dir` (removed afterwards).
fn realize(text: &str, seed: u64, dir: &Path, grid: &Grid) -> Result<Realization, StageError> {
    let failure = |e: std::io::Error| StageError::failure(format!("{}: {e}", dir.display()));
    std::fs::create_dir_all(dir).map_err(failure)?;
    let scene_path = dir.join("scene.toml");
    std::fs::write(&scene_path, with_seed(text, seed)?).map_err(failure)?;
    for stage in [Stage::Sampling, Stage::Costgraph, Stage::Skeleton] {
        InProcess.run(stage, &scene_path, dir)?;
    }
    let (_, skeleton) = read_artifact::<Skeleton>(&dir.join(Stage::Skeleton.file_name()))?;
    let report = report(&skeleton).map_err(|e| StageError::input(format!("seed {seed}: skeleton: {e}")))?;
    let cells = grid.cells_of(&skeleton);
    std::fs::remove_dir_all(dir).map_err(failure)?;
    Ok(Realization { seed, report, cells })
}

/// The scene text with its top-level `seed` replaced.
fn with_seed(text: &str, seed: u64) -> Result<String, StageError> {
    let mut table: toml::Table = text.parse().map_err(|e| StageError::input(format!("scene: {e}")))?;
    let seed = i64::try_from(seed).map_err(|_| StageError::input(format!("seed {seed} is too large")))?;
    table.insert("seed".into(), toml::Value::Integer(seed));
    Ok(table.to_string())
}

/// The probability grid over the scene domain.
struct Grid {
    min: [f64; 3],
    cell: f64,
    dims: [usize; 3],
}

impl Grid {
    fn new(scene: &Scene, cell: f64) -> Result<Self, StageError> {
        let (min, max) = (scene.domain.min, scene.domain.max);
        let dims = [0, 1, 2].map(|a| ((max[a] - min[a]) / cell).ceil().max(1.0) as usize);
        if dims.iter().product::<usize>() > 50_000_000 {
            return Err(StageError::input(format!(
                "ensemble: --cell {cell} m makes a grid of {dims:?} cells; choose a larger cell"
            )));
        }
        Ok(Self { min, cell, dims })
    }

    fn len(&self) -> usize {
        self.dims.iter().product()
    }

    /// Index of the cell holding `p`, if inside.
    fn index(&self, p: [f64; 3]) -> Option<usize> {
        let mut ijk = [0usize; 3];
        for a in 0..3 {
            let t = ((p[a] - self.min[a]) / self.cell).floor();
            if !(t >= 0.0 && t < self.dims[a] as f64) {
                return None;
            }
            ijk[a] = t as usize;
        }
        Some((ijk[2] * self.dims[1] + ijk[1]) * self.dims[0] + ijk[0])
    }

    /// Sorted, distinct cells crossed by the skeleton's conduits.
    fn cells_of(&self, skeleton: &Skeleton) -> Vec<usize> {
        let mut cells = Vec::new();
        for [a, b] in skeleton.links() {
            let (pa, pb) = (skeleton.nodes[a as usize].position, skeleton.nodes[b as usize].position);
            let length = (0..3).map(|i| (pb[i] - pa[i]).powi(2)).sum::<f64>().sqrt();
            let steps = (length / (self.cell / 4.0)).ceil().max(1.0) as usize;
            for s in 0..=steps {
                let t = s as f64 / steps as f64;
                cells.extend(self.index([0, 1, 2].map(|i| pa[i] + (pb[i] - pa[i]) * t)));
            }
        }
        cells.sort_unstable();
        cells.dedup();
        cells
    }

    /// Column (x, y) of a cell index.
    fn column(&self, index: usize) -> usize {
        index % (self.dims[0] * self.dims[1])
    }
}

fn write_outputs(args: &EnsembleArgs, grid: &Grid, realizations: &[Realization]) -> Result<(), StageError> {
    let failure =
        |path: &Path, e: &dyn std::fmt::Display| StageError::failure(format!("{}: {e}", path.display()));
    std::fs::create_dir_all(args.out.join("probability")).map_err(|e| failure(&args.out, &e))?;
    let table = table(realizations);
    let metrics_csv = args.out.join("metrics.csv");
    std::fs::write(&metrics_csv, csv(&table)).map_err(|e| failure(&metrics_csv, &e))?;
    let summary_csv = args.out.join("summary.csv");
    std::fs::write(&summary_csv, summary(&table)).map_err(|e| failure(&summary_csv, &e))?;
    let n = realizations.len() as f64;
    let mut cells = vec![0u32; grid.len()];
    let mut columns = vec![0u32; grid.dims[0] * grid.dims[1]];
    for r in realizations {
        for &c in &r.cells {
            cells[c] += 1;
        }
        let mut touched: Vec<usize> = r.cells.iter().map(|&c| grid.column(c)).collect();
        touched.sort_unstable();
        touched.dedup();
        for c in touched {
            columns[c] += 1;
        }
    }
    let grid_json = args.out.join("probability/grid.json");
    let placement = serde_json::json!({
        "min": grid.min, "cell": grid.cell, "dims": grid.dims, "realizations": realizations.len(),
    });
    std::fs::write(&grid_json, placement.to_string()).map_err(|e| failure(&grid_json, &e))?;
    let layer = grid.dims[0] * grid.dims[1];
    for z in 0..grid.dims[2] {
        let path = args.out.join(format!("probability/z-{z:03}.exr"));
        let slice: Vec<f32> =
            cells[z * layer..(z + 1) * layer].iter().map(|&c| (f64::from(c) / n) as f32).collect();
        write_exr(&path, grid.dims[0], grid.dims[1], &slice).map_err(|e| failure(&path, &e))?;
    }
    let png = args.out.join("probability-top.png");
    let probabilities: Vec<f64> = columns.iter().map(|&c| f64::from(c) / n).collect();
    top_view(grid, &probabilities, realizations.len()).write_png(&png).map_err(|e| failure(&png, &e))
}

/// Column names and one row of values per realization.
struct Table {
    columns: Vec<String>,
    rows: Vec<Vec<f64>>,
}

fn table(realizations: &[Realization]) -> Table {
    let first = &realizations[0].report;
    let mut columns = vec!["seed".to_string()];
    columns.extend(first.network.to_pairs().into_iter().map(|(k, _)| k.to_string()));
    columns.extend(["vadose length".to_string(), "phreatic length".to_string()]);
    columns.extend(first.conduit_types.keys().map(|t| format!("{t} length")));
    let rows = realizations
        .iter()
        .map(|r| {
            let mut row = vec![r.seed as f64];
            row.extend(r.report.network.to_pairs().into_iter().map(|(_, v)| v));
            row.extend([r.report.zones.vadose, r.report.zones.phreatic]);
            row.extend(r.report.conduit_types.values().copied());
            row
        })
        .collect();
    Table { columns, rows }
}

fn csv(table: &Table) -> String {
    let mut out = quoted(&table.columns).join(",") + "\n";
    for row in &table.rows {
        let cells: Vec<String> =
            row.iter().map(|v| if v.is_finite() { v.to_string() } else { String::new() }).collect();
        out += &(cells.join(",") + "\n");
    }
    out
}

fn quoted(names: &[String]) -> Vec<String> {
    names.iter().map(|n| format!("\"{n}\"")).collect()
}

/// Min, mean, max per column (seed excluded) and, for karstnet's metrics, the real-cave range.
fn summary(table: &Table) -> String {
    let ranges = real_cave_ranges();
    let mut out = String::from("metric,min,mean,max,defined,real_caves_min,real_caves_max,fraction_inside\n");
    for (c, name) in table.columns.iter().enumerate().skip(1) {
        let values: Vec<f64> = table.rows.iter().map(|r| r[c]).filter(|v| v.is_finite()).collect();
        let (min, max) =
            values.iter().fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), &v| (a.min(v), b.max(v)));
        let mean = values.iter().sum::<f64>() / values.len() as f64;
        let show = |v: f64| if v.is_finite() { v.to_string() } else { String::new() };
        let _ = write!(out, "\"{name}\",{},{},{},{}", show(min), show(mean), show(max), values.len());
        match CHARACTERIZE_KEYS.contains(&name.as_str()).then(|| &ranges[name]) {
            Some(r) => {
                let inside = table.rows.iter().filter(|row| r.contains(row[c])).count();
                let _ = writeln!(out, ",{},{},{}", r.min, r.max, inside as f64 / table.rows.len() as f64);
            }
            None => out.push_str(",,,\n"),
        }
    }
    out
}

/// One float channel `P`, scanlines from y = 0 (south) up, ZIP-compressed, written serially.
fn write_exr(path: &Path, width: usize, height: usize, values: &[f32]) -> Result<(), exr::error::Error> {
    use exr::prelude::*;
    let pixels = SpecificChannels::build()
        .with_channel("P")
        .with_pixel_fn(|p: Vec2<usize>| (values[p.1 * width + p.0],));
    Image::from_encoded_channels((width, height), Encoding::SMALL_LOSSLESS, pixels)
        .write()
        .non_parallel()
        .to_file(path)
}

/// The top-view probability as a picture, north up, with a colour bar.
fn top_view(grid: &Grid, probabilities: &[f64], n: usize) -> Canvas {
    let [nx, ny, _] = grid.dims;
    let scale = (600 / nx.max(ny)).max(1);
    let (map_w, map_h) = (nx * scale, ny * scale);
    let mut c = Canvas::new(map_w as u32 + 120, map_h as u32 + 40, WHITE);
    for iy in 0..ny {
        for ix in 0..nx {
            let colour = ramp(probabilities[iy * nx + ix]);
            let (x0, y0) = ((ix * scale) as f64, ((ny - 1 - iy) * scale + 30) as f64);
            c.rect((x0, y0), (x0 + scale as f64, y0 + scale as f64), colour);
        }
    }
    c.text((4, 8), &format!("Conduit probability, {n} realizations, {} m cells", grid.cell), 1, BLACK);
    let bar_x = map_w as f64 + 30.0;
    for k in 0..=100 {
        let y = 30.0 + (100 - k) as f64 * 2.0;
        c.rect((bar_x, y), (bar_x + 20.0, y + 2.0), ramp(k as f64 / 100.0));
    }
    c.text((bar_x as i64 + 24, 30), "1", 1, BLACK);
    c.text((bar_x as i64 + 24, 226), "0", 1, BLACK);
    c
}

/// White at 0, then pale yellow through orange to dark red at 1.
fn ramp(p: f64) -> [u8; 3] {
    if p <= 0.0 {
        return WHITE;
    }
    let t = p.clamp(0.0, 1.0);
    let lerp = |a: f64, b: f64| (a + (b - a) * t).round() as u8;
    [lerp(255.0, 130.0), lerp(230.0, 0.0), lerp(120.0, 20.0)]
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn seed_is_replaced_and_the_rest_kept() {
        let text = "name = \"x\"\nseed = 7\n[domain]\nmin = [0.0, 0.0, 0.0]\n";
        let out: toml::Table = with_seed(text, 42).unwrap().parse().unwrap();
        assert_eq!(out["seed"].as_integer(), Some(42));
        assert_eq!(out["name"].as_str(), Some("x"));
        assert!(out["domain"].get("min").is_some());
    }

    #[test]
    fn summary_skips_undefined_values_and_counts_inside() {
        let table = Table {
            columns: vec!["seed".into(), "tortuosity".into(), "n_branches".into()],
            rows: vec![vec![1.0, 1.2, 3.0], vec![2.0, f64::NAN, 5.0], vec![3.0, 2.0, 4.0]],
        };
        let s = summary(&table);
        let lines: Vec<&str> = s.lines().collect();
        assert!(lines[1].starts_with("\"tortuosity\",1.2,1.6,2,2,"), "{}", lines[1]);
        assert!(lines[1].ends_with(&format!(",{}", 1.0 / 3.0)), "{}", lines[1]);
        assert_eq!(lines[2], "\"n_branches\",3,4,5,3,,,");
    }

    fn run_with_threads(threads: usize, out: &Path) -> Vec<(String, Vec<u8>)> {
        let scene = Path::new(env!("CARGO_MANIFEST_DIR")).join("../fixtures/scenes/tiny.toml");
        let args = EnsembleArgs { scene, n: 3, cell: 20.0, out: out.to_path_buf() };
        let pool = rayon::ThreadPoolBuilder::new().num_threads(threads).build().unwrap();
        pool.install(|| run(&args)).unwrap();
        let mut files: Vec<PathBuf> = ["metrics.csv", "summary.csv", "probability-top.png"]
            .iter()
            .map(|f| out.join(f))
            .chain(std::fs::read_dir(out.join("probability")).unwrap().map(|e| e.unwrap().path()))
            .collect();
        files.sort();
        files
            .into_iter()
            .map(|f| (f.strip_prefix(out).unwrap().display().to_string(), std::fs::read(f).unwrap()))
            .collect()
    }

    #[test]
    fn outputs_do_not_depend_on_the_thread_count() {
        let base = std::env::temp_dir().join(format!("karstgen-ensemble-test-{}", std::process::id()));
        let one = run_with_threads(1, &base.join("one"));
        let two = run_with_threads(2, &base.join("two"));
        std::fs::remove_dir_all(&base).unwrap();
        assert_eq!(one.len(), two.len());
        for ((name, a), (_, b)) in one.iter().zip(&two) {
            assert!(a == b, "{name} differs between 1 and 2 threads");
        }
        let csv = String::from_utf8(one.iter().find(|(n, _)| n == "metrics.csv").unwrap().1.clone()).unwrap();
        assert_eq!(csv.lines().count(), 4, "a header and one row per seed");
        let seeds: Vec<&str> = csv.lines().skip(1).map(|l| l.split(',').next().unwrap()).collect();
        assert_eq!(seeds.len(), 3);
        assert!(seeds[0] != seeds[1] && seeds[1] != seeds[2]);
    }
}
