//! What a run folder holds besides the artifacts: which scene it was made from.
//!
//! `karstgen run` leaves the scene's absolute path in `DIR/scene.path` (or the scene itself in
//! `DIR/scene.toml` for the embedded default scene), so that the commands that work on a run
//! afterwards (`karstgen export`, `karstgen view`) find its scene without being told.

use std::path::{Path, PathBuf};

/// The scene file written into a run folder (the embedded default scene).
pub const SCENE_FILE: &str = "scene.toml";
/// The file holding the absolute path of a run's scene.
pub const SCENE_PATH_FILE: &str = "scene.path";

/// Records `scene` as the scene of the run in `dir` (nothing to do when it lives there).
pub fn record_scene(dir: &Path, scene: &Path) -> std::io::Result<()> {
    if scene == dir.join(SCENE_FILE) {
        return Ok(());
    }
    let absolute = std::path::absolute(scene)?;
    karst_artifact::atomic::write_bytes(&dir.join(SCENE_PATH_FILE), absolute.to_string_lossy().as_bytes())
}

/// The scene of the run in `dir`: its own `scene.toml`, else the file `scene.path` names.
pub fn scene_of(dir: &Path) -> Option<PathBuf> {
    let own = dir.join(SCENE_FILE);
    if own.is_file() {
        return Some(own);
    }
    // A path, not a FIFO to block on or a file to read for ever.
    let named = karst_artifact::files::read_regular_text(&dir.join(SCENE_PATH_FILE), 64 << 10).ok()?;
    Some(PathBuf::from(named.trim())).filter(|p| p.is_file())
}
