//! Where a run's scene comes from: a scene file, or the embedded default scene written into
//! the output folder with its data files. Paths on the command line are the user's (relative to
//! the working folder); the data files a scene names are relative to the scene's own folder.

use std::path::{Path, PathBuf};

use karst_scene::Scene;
use karst_stage::StageError;

/// The embedded default scene, run when no scene is given.
const DEFAULT_SCENE: &str = include_str!("../../../fixtures/scenes/default.toml");
/// The data files the default scene names, written beside it (paths relative to the scene).
const DEFAULT_DATA: &[(&str, &[u8])] = &[
    ("data/plateau.png", include_bytes!("../../../fixtures/scenes/data/plateau.png")),
    ("data/marl-parting.ts", include_bytes!("../../../fixtures/scenes/data/marl-parting.ts")),
];

/// A loaded scene and the file it was read from (named in messages).
#[derive(Debug, Clone)]
pub struct SceneFile {
    pub path: PathBuf,
    pub scene: Scene,
}

impl SceneFile {
    /// Reads and validates the scene at `path`, and the calibration target its `[calibrate]`
    /// names (an unknown `like` or an unreadable `target` is refused now, not at the metrics).
    pub fn load(path: &Path) -> Result<SceneFile, StageError> {
        let file = SceneFile { path: path.to_path_buf(), scene: Scene::load(path)? };
        file.check_aim()?;
        Ok(file)
    }

    /// Parses scene text named `path` (data files are read relative to its folder), as
    /// [`SceneFile::load`] reads a file.
    pub fn parse(text: &str, path: &Path) -> Result<SceneFile, StageError> {
        let scene = Scene::parse(text, path).map_err(StageError::from)?;
        let file = SceneFile { path: path.to_path_buf(), scene };
        file.check_aim()?;
        Ok(file)
    }

    /// Resolves the calibration target the scene names, if any: a bad one is bad input.
    fn check_aim(&self) -> Result<(), StageError> {
        let Some(aim) = self.scene.calibrate().as_ref().and_then(|c| c.aim()) else { return Ok(()) };
        karst_metrics::stage::resolve(aim)
            .map(|_| ())
            .map_err(|e| StageError::input(format!("{}: {e}", self.path.display())))
    }

    /// The embedded default scene, written (with its data files) into `out` when they differ,
    /// then loaded from there.
    pub fn default_in(out: &Path) -> Result<SceneFile, StageError> {
        for (file, bytes) in DEFAULT_DATA {
            write_if_changed(&out.join(file), bytes)?;
        }
        let path = out.join("scene.toml");
        write_if_changed(&path, DEFAULT_SCENE.as_bytes())?;
        SceneFile::load(&path)
    }

    /// The same scene with another seed (an ensemble's realization).
    pub fn with_seed(&self, seed: u64) -> SceneFile {
        let mut scene = self.scene.clone();
        scene.set_seed(seed);
        SceneFile { path: self.path.clone(), scene }
    }
}

/// The name of the embedded default scene.
pub const DEFAULT_NAME: &str = "default";

/// The default output folder of a scene: `out/<scene name>`.
pub fn default_out(scene: &Scene) -> PathBuf {
    PathBuf::from("out").join(scene.name())
}

/// Writes `bytes` to `path` atomically unless it already holds them.
pub fn write_if_changed(path: &Path, bytes: &[u8]) -> Result<(), StageError> {
    if std::fs::read(path).ok().as_deref() == Some(bytes) {
        return Ok(());
    }
    if let Some(folder) = path.parent() {
        std::fs::create_dir_all(folder)
            .map_err(|e| StageError::failure(format!("{}: cannot create: {e}", folder.display())))?;
    }
    karst_artifact::atomic::write_bytes(path, bytes)
        .map_err(|e| StageError::failure(format!("{}: cannot write: {e}", path.display())))
}
