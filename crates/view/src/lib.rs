//! The web viewer of a karstgen run (docs/viewer.md).
//!
//! [`write_view`] turns a run folder into `RUN/view/`, a static site that any local web server
//! can serve and that loads nothing from the internet:
//!
//! - `index.html`, the app's ES modules (`js/`) and stylesheet, and the vendored three.js
//!   (`vendor/three/`, with its licence), all embedded in this crate ([`app`]);
//! - `data/run.json`: the network, the water, the surface streams, the routes, the key points,
//!   the water tables and horizons, the metrics, what is missing from the run, and the
//!   manifest of the meshes ([`data`]);
//! - `data/<surface>/cNNN-lK.glb`: the carved terrain, the cave and the water, split into
//!   chunks ([`chunks`]), each at up to four levels of detail ([`lod`]), compressed with
//!   EXT_meshopt_compression and KHR_mesh_quantization ([`glb`]), which three.js decodes
//!   natively. The page loads the coarsest level of every chunk first, then refines the chunks
//!   in view until their error is below a pixel or two.
//!
//! [`Server`] / [`serve`] serve a view folder on 127.0.0.1 only.
//!
//! The view is written into a temporary folder beside the run's files and renamed to `view/`
//! at the end, so an interrupted write leaves the previous view whole; the run's artifacts
//! are only read.

pub mod app;
pub mod chunks;
pub mod cli;
pub mod data;
pub mod ensemble;
mod error;
pub mod glb;
pub mod lod;
pub mod meshes;
pub mod run;
pub mod server;

use std::path::{Path, PathBuf};

pub use error::ViewError;
pub use run::{Problem, Run};
pub use server::{Server, serve};

/// The folder, inside the run, that [`write_view`] writes.
pub const VIEW_DIR: &str = "view";

/// What [`write_view`] wrote.
#[derive(Debug, Clone)]
pub struct ViewReport {
    /// RUN/view.
    pub dir: PathBuf,
    /// Files written and their total size.
    pub files: usize,
    pub bytes: u64,
    /// Per surface: name, chunks, full triangles.
    pub meshes: Vec<(String, usize, usize)>,
    /// What the run lacks; the page lists it too.
    pub problems: Vec<Problem>,
}

impl ViewReport {
    /// One line for the terminal.
    pub fn headline(&self) -> String {
        let meshes: Vec<String> =
            self.meshes.iter().map(|(n, c, t)| format!("{n} {t} triangles in {c} chunks")).collect();
        format!(
            "{}: {} files, {:.1} MB{}{}",
            self.dir.display(),
            self.files,
            self.bytes as f64 / 1e6,
            if meshes.is_empty() { String::new() } else { format!("; {}", meshes.join(", ")) },
            if self.problems.is_empty() {
                String::new()
            } else {
                format!("; {} problem(s), listed on the page", self.problems.len())
            }
        )
    }
}

/// Writes `run_dir/view/` for the run in `run_dir`; `scene` is the scene file it was made
/// from, when the run folder has no `scene.toml` of its own.
///
/// The run folder is locked while the view is written (a run writing into it meanwhile would
/// change what the view shows; two views would replace each other's folder), and what a killed
/// writer left there (a staging folder `.view.tmp-PID`) is removed first.
pub fn write_view(run_dir: &Path, scene: Option<&Path>) -> Result<ViewReport, ViewError> {
    let run = Run::load(run_dir, scene)?;
    let _lock = karst_artifact::lock_output(run_dir)?;
    karst_artifact::atomic::remove_stale_temporaries(run_dir);
    let staging = run_dir.join(format!(".{VIEW_DIR}.tmp-{}", std::process::id()));
    let result = fill(&run, &staging);
    if result.is_err() {
        let _ = std::fs::remove_dir_all(&staging);
    }
    let meshes = result?;
    let dir = run_dir.join(VIEW_DIR);
    let replace = |e: std::io::Error| ViewError::Write { path: dir.clone(), source: e };
    if dir.exists() {
        std::fs::remove_dir_all(&dir).map_err(replace)?;
    }
    std::fs::rename(&staging, &dir).map_err(replace)?;
    let (files, bytes) = size_of(&dir);
    Ok(ViewReport {
        dir,
        files,
        bytes,
        meshes: meshes.iter().map(|m| (m.name.clone(), m.chunks.len(), m.triangles)).collect(),
        problems: run.problems,
    })
}

/// Writes the app, the meshes and run.json into `dir`.
fn fill(run: &Run, dir: &Path) -> Result<Vec<meshes::MeshView>, ViewError> {
    let _ = std::fs::remove_dir_all(dir);
    app::write(dir)?;
    let meshes = match &run.mesh {
        Some(mesh) => meshes::write(dir, mesh)?,
        None => Vec::new(),
    };
    let path = dir.join("data/run.json");
    let document = data::view_data(run, &meshes);
    let json = serde_json::to_vec(&document).map_err(|e| ViewError::Encode {
        path: path.clone(),
        what: "view data".into(),
        detail: e.to_string(),
    })?;
    std::fs::create_dir_all(dir.join("data"))
        .map_err(|source| ViewError::Write { path: dir.into(), source })?;
    std::fs::write(&path, json).map_err(|source| ViewError::Write { path, source })?;
    Ok(meshes)
}

/// Files under `dir` and their total size.
fn size_of(dir: &Path) -> (usize, u64) {
    let Ok(entries) = std::fs::read_dir(dir) else { return (0, 0) };
    entries.flatten().fold((0, 0), |(n, b), e| match e.metadata() {
        Ok(m) if m.is_dir() => {
            let (n2, b2) = size_of(&e.path());
            (n + n2, b + b2)
        }
        Ok(m) => (n + 1, b + m.len()),
        Err(_) => (n, b),
    })
}
