//! The export's work estimate (`karst_export::estimate`) against the bytes really written.

mod common;

use common::{Run, export_with, tiny};
use karst_export::estimate::{Counts, format_bytes};
use karst_export::{ExportFormat, ExportParams};

#[test]
fn estimated_bytes_are_within_a_factor_two_of_the_files() {
    let run = Run::load(&tiny());
    // Every format but the GIS ones (their estimate is an upper bound: mostly no-data rasters
    // and SQLite pages), the glb at full resolution so that its estimate is not its bound.
    let formats: Vec<ExportFormat> = ExportFormat::ALL
        .into_iter()
        .filter(|f| !matches!(f, ExportFormat::Gpkg | ExportFormat::Geotiff))
        .collect();
    let params = ExportParams { formats: formats.clone(), gltf_full: true, ..ExportParams::default() };
    let (_scratch, _, manifest) = export_with(&run, &params, "estimate");
    let counts = Counts::of(
        Some(&run.skeleton),
        Some(&run.samples),
        Some(&run.streams),
        run.mesh.as_ref(),
        &params.surfaces,
    );
    let (mut estimated, mut written) = (0.0, 0.0);
    for format in formats {
        let real: u64 = manifest.files.iter().filter(|f| f.format == format.name()).map(|f| f.bytes).sum();
        let guess = format_bytes(format, &counts, &params, 0.0);
        estimated += guess;
        written += real as f64;
        // Small files are mostly their headers, which the estimate rounds up.
        if real > 1 << 16 {
            let ratio = guess / real as f64;
            assert!((0.5..=2.0).contains(&ratio), "{}: estimated {guess}, wrote {real}", format.name());
        }
    }
    let ratio = estimated / written;
    assert!((0.5..=2.0).contains(&ratio), "all: estimated {estimated}, wrote {written}");
}
