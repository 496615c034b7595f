//! The GeoTIFF budget: reading a 4000 × 4000 float32 LZW GeoTIFF and building the
//! terrain from it, ≤ 1.5 s and ≤ 200 MB above the raster's own size (64 MB of float32).
//!
//! The raster (a smooth DEM with centimetre detail, one row per strip as GDAL writes LZW floats,
//! 1 m pixels in Lambert-93) is written once into a scratch folder; each run loads a scene whose
//! domain covers all of it, so the whole raster is decoded, converted to elevations and its
//! Lipschitz bound computed, and the file hashed.

use std::path::{Path, PathBuf};
use std::time::Instant;

use karst_geodata::geotiff::testing::{Encoding, write};
use karst_scene::Scene;
use karst_stage::StageError;

use crate::temp_folder::TempFolder;

use super::probes;

/// Pixels along each side of the benchmark raster.
pub const SIDE: u32 = 4000;

/// One measurement of the GeoTIFF case.
#[derive(Debug, Clone)]
pub struct GeotiffTiming {
    pub file_bytes: u64,
    /// Median wall seconds of `Scene::load`.
    pub seconds: f64,
    /// CPU seconds of the median's run (user + system), when the platform says.
    pub cpu_seconds: Option<f64>,
    /// Peak resident memory above the process's before the load, bytes.
    pub peak_above: Option<u64>,
}

/// Writes the raster, then loads the scene `runs` times.
pub fn time_geotiff_terrain(runs: usize) -> Result<GeotiffTiming, StageError> {
    let folder = TempFolder::new("bench-geotiff");
    std::fs::create_dir_all(&folder)
        .map_err(|e| StageError::failure(format!("{}: {e}", folder.display())))?;
    let scene = write_case(&folder).map_err(|e| StageError::failure(format!("{}: {e}", folder.display())))?;
    let file_bytes = std::fs::metadata(folder.join("dem.tif")).map(|m| m.len()).unwrap_or(0);
    let mut times = Vec::new();
    for _ in 0..runs.max(1) {
        probes::reset_peak_memory();
        let before = probes::resident_memory();
        let cpu = probes::cpu_seconds();
        let start = Instant::now();
        let loaded = Scene::load(&scene)?;
        let seconds = start.elapsed().as_secs_f64();
        let cpu = cpu.zip(probes::cpu_seconds()).map(|(a, b)| b - a);
        let peak = probes::peak_memory().zip(before).map(|(p, b)| p.saturating_sub(b));
        drop(loaded);
        times.push((seconds, cpu, peak));
    }
    times.sort_by(|a, b| a.0.total_cmp(&b.0));
    let (seconds, cpu_seconds, peak_above) = times[times.len() / 2];
    Ok(GeotiffTiming { file_bytes, seconds, cpu_seconds, peak_above })
}

/// The raster and a scene whose domain covers every pixel centre.
fn write_case(folder: &Path) -> Result<PathBuf, Box<dyn std::error::Error>> {
    let side = SIDE as usize;
    let values: Vec<f32> = (0..side * side)
        .map(|k| {
            let (c, r) = ((k % side) as f64, (k / side) as f64);
            let h = 600.0 + 0.05 * c - 0.03 * r + 12.0 * (c / 170.0).sin() * (r / 230.0).cos();
            ((h * 100.0).round() / 100.0) as f32
        })
        .collect();
    let encoding = Encoding {
        corner: [600_000.0, 6_904_000.0],
        scale: Some([1.0, 1.0]),
        compression: tiff::encoder::Compression::Lzw,
        rows_per_strip: 1,
        ..Encoding::default()
    };
    write(&folder.join("dem.tif"), SIDE, SIDE, &values, &encoding)?;
    let scene = folder.join("scene.toml");
    std::fs::write(
        &scene,
        r#"name = "geotiff-bench"
crs = "EPSG:2154"
[domain]
min = [600001, 6900001, 0]
max = [603999, 6903999, 800]
[terrain]
kind = "heightfield"
file = "dem.tif"
[[geology.water_tables]]
name = "wt"
elevation = 400
[[keypoints]]
name = "sink"
kind = "sink"
position = [601000, 6901000, 550]
[[keypoints]]
name = "spring"
kind = "spring"
position = [603000, 6903000, 400]
water_table = "wt"
"#,
    )?;
    Ok(scene)
}
