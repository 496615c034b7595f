//! `karstgen view DIR [--scene SCENE] [--serve] [--port N]` (and `cargo xtask view`): writes
//! DIR/view/ for the run in DIR and, with `--serve`, serves it on 127.0.0.1 until Ctrl-C.

use std::path::PathBuf;

use karst_stage::StageError;

use crate::{ViewError, serve, write_view};

/// The arguments of `karstgen view`.
#[derive(Debug, Clone, clap::Args)]
pub struct ViewArgs {
    /// The run's output folder (`karstgen run SCENE --out DIR`).
    pub dir: PathBuf,
    /// The scene the run was made from (default: the one `karstgen run` recorded in DIR).
    #[arg(long)]
    pub scene: Option<PathBuf>,
    /// Serve DIR/view on 127.0.0.1 and print its URL.
    #[arg(long)]
    pub serve: bool,
    /// Port to serve on (0: any free port).
    #[arg(long, default_value_t = 8080, requires = "serve")]
    pub port: u16,
}

/// Writes the view (and serves it when asked), warning about what the run lacks.
pub fn view(args: &ViewArgs) -> Result<(), StageError> {
    let report = write_view(&args.dir, args.scene.as_deref()).map_err(to_stage_error)?;
    println!("view {}", report.headline());
    for problem in &report.problems {
        eprintln!("warning: {}: {}", problem.file, problem.message);
    }
    if args.serve {
        serve(&report.dir, args.port).map_err(to_stage_error)?;
    } else {
        println!(
            "open it with `karstgen view {} --serve` (or any static server on that folder)",
            args.dir.display()
        );
    }
    Ok(())
}

fn to_stage_error(e: ViewError) -> StageError {
    if e.exit_code() == 2 { StageError::input(e) } else { StageError::failure(e) }
}
