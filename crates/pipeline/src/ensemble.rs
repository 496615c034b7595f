//! `karstgen ensemble SCENE --n 50`: many realizations of one scene, differing only by seed.
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

use karst_artifact::{StageId, read_artifact};
use karst_geology::Scene;
use karst_metrics::ranges::{CHARACTERIZE_KEYS, real_cave_ranges};
use karst_metrics::{MetricsReport, report};
use karst_plot::axes::{self, Axes};
use karst_plot::colour_bar::{BAR_WIDTH, ColourBar, ColourMap};
use karst_plot::text::{self, Align, Valign};
use karst_plot::{Canvas, Rect, WHITE, ticks};
use karst_skeleton::Skeleton;
use karst_stage::{Job, StageError};

use crate::registry;
use crate::scene::SceneFile;

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
    let scene = SceneFile::load(&args.scene)?;
    let grid = Grid::new(&scene.scene, args.cell)?;
    static RUNS: AtomicUsize = AtomicUsize::new(0);
    let run_id = RUNS.fetch_add(1, Ordering::Relaxed);
    let scratch = std::env::temp_dir().join(format!("karstgen-ensemble-{}-{run_id}", std::process::id()));
    let bar = karst_stage::progress::bar(args.n as u64, "ensemble");
    let realizations: Result<Vec<Realization>, StageError> = (0..args.n as u64)
        .into_par_iter()
        .map(|k| {
            let first = scene.scene.seed();
            let seed = first.checked_add(k).filter(|s| i64::try_from(*s).is_ok()).ok_or_else(|| {
                StageError::input(format!("{}: seed {first} + {k} is too large", args.scene.display()))
            })?;
            let r = realize(&scene.with_seed(seed), &scratch.join(format!("seed-{seed}")), &grid);
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

/// Runs one realization in `dir` (removed afterwards).
fn realize(scene: &SceneFile, dir: &Path, grid: &Grid) -> Result<Realization, StageError> {
    let failure = |e: std::io::Error| StageError::failure(format!("{}: {e}", dir.display()));
    std::fs::create_dir_all(dir).map_err(failure)?;
    let job = Job { scene_path: &scene.path, scene: &scene.scene, out: dir };
    for stage in [StageId::Sampling, StageId::Costgraph, StageId::Skeleton] {
        registry::stage(stage).run(&job)?;
    }
    let seed = scene.scene.seed();
    let (_, skeleton) = read_artifact::<Skeleton>(&job.artifact(StageId::Skeleton))?;
    let report = report(&skeleton).map_err(|e| StageError::input(format!("seed {seed}: skeleton: {e}")))?;
    let cells = grid.cells_of(&skeleton);
    std::fs::remove_dir_all(dir).map_err(failure)?;
    Ok(Realization { seed, report, cells })
}

/// The probability grid over the scene domain.
struct Grid {
    min: [f64; 3],
    cell: f64,
    dims: [usize; 3],
}

impl Grid {
    fn new(scene: &Scene, cell: f64) -> Result<Self, StageError> {
        let (min, max) = (scene.domain().min, scene.domain().max);
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

/// The top-view probability as a map: cells on axes in metres (north up), a colour bar, a
/// scale bar and a north arrow.
fn top_view(grid: &Grid, probabilities: &[f64], n: usize) -> Canvas {
    let [nx, ny, _] = grid.dims;
    let zoom = (600 / nx.max(ny)).max(1) as f64;
    let frame = Rect::at(axes::LEFT, 64.0, nx as f64 * zoom, ny as f64 * zoom);
    let bar = probability_bar();
    let bar_box =
        Rect::at(frame.x1 + 24.0, frame.y0 + ColourBar::title_height(), BAR_WIDTH, frame.height().min(240.0));
    let extent = |a: usize| (grid.min[a], grid.min[a] + grid.dims[a] as f64 * grid.cell);
    let map = Axes::new(frame, extent(0), extent(1));
    let furniture_at = (bar_box.x0, bar_box.y1 + 20.0);
    let (furniture_w, furniture_h) = karst_plot::map::panel_size(&map);
    let width = bar_box.x0 + bar.width(bar_box.height()).max(furniture_w) + 16.0;
    let height = (frame.y1 + axes::BOTTOM + 8.0).max(furniture_at.1 + furniture_h + 8.0);
    let mut c = Canvas::new(width.ceil() as u32, height.ceil() as u32, WHITE);
    for iy in 0..ny {
        for ix in 0..nx {
            let (x0, y0) = (frame.x0 + ix as f64 * zoom, frame.y0 + (ny - 1 - iy) as f64 * zoom);
            c.fill_rect(Rect::at(x0, y0, zoom, zoom), bar.colour(probabilities[iy * nx + ix]));
        }
    }
    karst_plot::map::draw_panel(&mut c, &map, furniture_at);
    map.draw(&mut c, "easting x (m)", "northing y (m)");
    bar.draw(&mut c, bar_box);
    let title = format!("Conduit probability of {n} realizations, {} m cells", ticks::human(grid.cell));
    text::draw(&mut c, &title, (axes::LEFT, 10.0), text::TITLE, Align::Left, Valign::Top);
    let caption = "fraction of realizations with a conduit anywhere in each column of cells (white: none)";
    text::draw(&mut c, caption, (axes::LEFT, 36.0), text::SMALL, Align::Left, Valign::Top);
    c
}

/// White at 0, then pale yellow through orange to dark red at 1.
fn probability_bar() -> ColourBar {
    ColourBar {
        map: ColourMap::new(&[(0.0, WHITE), (1e-9, [255, 230, 120]), (1.0, [130, 0, 20])]),
        range: (0.0, 1.0),
        title: "fraction of realizations".into(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

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

    #[test]
    fn the_probability_map_decodes_at_its_size() {
        let grid = Grid { min: [0.0; 3], cell: 10.0, dims: [30, 20, 4] };
        let p: Vec<f64> = (0..600).map(|i| f64::from(i % 7) / 6.0).collect();
        let canvas = top_view(&grid, &p, 6);
        let mut bytes = Vec::new();
        canvas.encode_png(&mut bytes).unwrap();
        let (w, h, colours) = karst_plot::testing::png_summary(&bytes);
        // 20 px per cell: a 600 × 400 px map under the title, axes below it.
        assert_eq!(h, (64.0 + 400.0 + axes::BOTTOM + 8.0) as u32);
        assert!(w > 600 + axes::LEFT as u32 && colours > 10, "{w} px, {colours} colours");
        assert_eq!(canvas.get(axes::LEFT as i64 + 5, 64 + 395), Some(probability_bar().colour(0.0)));
    }

    fn run_with_threads(threads: usize, out: &Path) -> Vec<(String, Vec<u8>)> {
        let scene = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../fixtures/scenes/tiny.toml");
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
