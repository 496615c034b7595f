//! `cargo xtask bench --export DIR` times the export formats on a finished run (the artifacts
//! in DIR are read once; each format is exported into a scratch folder, median of the runs).

use std::path::Path;
use std::time::Instant;

use karst_artifact::read_artifact;
use karst_export::{ExportFormat, ExportParams, Input, Inputs, export, needs};
use karst_stage::StageError;

use crate::temp_folder::TempFolder;

/// One timed case: its name, median seconds and bytes written.
pub struct ExportTime {
    pub case: String,
    pub seconds: f64,
    pub bytes: u64,
}

/// Times the default formats together, then every format alone.
pub fn time_exports(dir: &Path, runs: usize) -> Result<Vec<ExportTime>, StageError> {
    let skeleton = read_artifact(&dir.join("skeleton.json"))?.1;
    let hydro = read_artifact(&dir.join("hydro.json"))?.1;
    let streams = read_artifact(&dir.join("streams.json"))?.1;
    let mesh = read_artifact(&dir.join("mesh.bin"))?.1;
    let metrics = read_artifact(&dir.join("metrics.json"))?.1;
    let (header, samples) = read_artifact(&dir.join("samples.bin"))?;
    let frame = header.frame();
    let inputs = Inputs {
        skeleton: Some(&skeleton),
        hydro: Some(&hydro),
        streams: Some(&streams),
        mesh: Some(&mesh),
        metrics: Some(&metrics),
        samples: Some(&samples),
        geology: None,
        keypoints: None,
        terrain: None,
        domain: None,
        frame: &frame,
    };
    let scratch = TempFolder::new("bench-export");
    let mut cases = vec![("default".to_string(), ExportParams::default().formats)];
    // The GIS formats read the scene too (its key points and terrain): not timed here.
    let artifacts_only = ExportFormat::ALL.into_iter().filter(|f| !needs(*f).contains(&Input::Scene));
    cases.extend(artifacts_only.map(|f| (f.name().to_string(), vec![f])));
    let mut times = Vec::new();
    for (case, formats) in cases {
        let params = ExportParams { formats, ..ExportParams::default() };
        let mut seconds = Vec::new();
        let mut bytes = 0;
        for _ in 0..runs.max(1) {
            let start = Instant::now();
            let manifest = export(&inputs, &params, &scratch).map_err(StageError::input)?;
            seconds.push(start.elapsed().as_secs_f64());
            bytes = manifest.files.iter().map(|f| f.bytes).sum();
            let _ = std::fs::remove_dir_all(&scratch);
        }
        seconds.sort_by(f64::total_cmp);
        times.push(ExportTime { case, seconds: seconds[seconds.len() / 2], bytes });
    }
    Ok(times)
}
