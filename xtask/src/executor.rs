//! How a stage is run: as its binary (what `cargo xtask run` does, so that each stage is an
//! independent, killable process) or in this process (what the tests and the benchmarks do).

use std::path::{Path, PathBuf};
use std::process::Command;

use karst_artifact::cli::RunArgs;
use karst_artifact::{Stage, StageError};

/// Runs one stage on a scene and an output folder, returning its headline.
pub trait Executor {
    fn run(&self, stage: Stage, scene: &Path, out: &Path) -> Result<String, StageError>;
}

/// Calls the stage libraries directly.
pub struct InProcess;

impl Executor for InProcess {
    fn run(&self, stage: Stage, scene: &Path, out: &Path) -> Result<String, StageError> {
        let args = RunArgs { scene: scene.to_path_buf(), out: out.to_path_buf() };
        match stage {
            Stage::Sampling => karst_sampling::stage::run(&args),
            Stage::Costgraph => karst_costgraph::stage::run(&args),
            Stage::Skeleton => karst_skeleton::stage::run(&args),
            Stage::Hydro => karst_hydro::stage::run(&args),
            Stage::Sdf => karst_sdf::stage::run(&args),
            Stage::Mesher => karst_mesher::stage::run(&args),
            Stage::Metrics => karst_metrics::stage::run(&args),
        }
    }
}

/// Spawns `karst-<stage> run` from a folder of built binaries.
pub struct Binaries {
    pub dir: PathBuf,
}

impl Binaries {
    /// Builds every stage binary in release mode (beside this xtask binary) and returns them.
    pub fn build() -> anyhow::Result<Binaries> {
        let cargo = std::env::var_os("CARGO").unwrap_or_else(|| "cargo".into());
        let mut command = Command::new(cargo);
        command.args(["build", "--release", "--quiet", "--bins"]);
        for stage in Stage::ALL {
            command.args(["--package", &format!("karst-{}", stage.name())]);
        }
        let status = command.status()?;
        anyhow::ensure!(status.success(), "building the stage binaries failed");
        let exe = std::env::current_exe()?;
        let dir = exe.parent().ok_or_else(|| anyhow::anyhow!("xtask binary has no folder"))?;
        Ok(Binaries { dir: dir.to_path_buf() })
    }
}

impl Executor for Binaries {
    fn run(&self, stage: Stage, scene: &Path, out: &Path) -> Result<String, StageError> {
        let binary = self.dir.join(stage.binary());
        let output = Command::new(&binary)
            .arg("run")
            .arg(scene)
            .arg("--out")
            .arg(out)
            .output()
            .map_err(|e| StageError::failure(format!("cannot start {}: {e}", binary.display())))?;
        let stderr = String::from_utf8_lossy(&output.stderr);
        let message = stderr.trim().trim_start_matches("error: ").to_string();
        match output.status.code() {
            Some(0) => Ok(String::from_utf8_lossy(&output.stdout).trim().to_string()),
            Some(2) => Err(StageError::input(message)),
            _ => Err(StageError::failure(format!("{} failed: {message}", stage.binary()))),
        }
    }
}
