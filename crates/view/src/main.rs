//! `karst-view DIR [--scene SCENE] [--serve] [--port N]`: writes DIR/view/ for the run in DIR
//! and, with `--serve`, serves it on 127.0.0.1 until Ctrl-C.

use std::path::PathBuf;
use std::process::ExitCode;

use clap::Parser;

use karst_view::{ViewError, serve, write_view};

#[derive(Parser)]
#[command(name = "karst-view", about = "Write (and serve) the web viewer of a karstgen run")]
struct Args {
    /// The run's output folder (`cargo xtask run SCENE --out DIR`).
    dir: PathBuf,
    /// The scene the run was made from (default: DIR/scene.toml when there is one).
    #[arg(long)]
    scene: Option<PathBuf>,
    /// Serve DIR/view on 127.0.0.1 and print its URL.
    #[arg(long)]
    serve: bool,
    /// Port to serve on (0: any free port).
    #[arg(long, default_value_t = 8080, requires = "serve")]
    port: u16,
}

fn main() -> ExitCode {
    karst_artifact::cli::default_sigpipe();
    let args = Args::parse();
    match run(&args) {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("error: {e}");
            ExitCode::from(e.exit_code())
        }
    }
}

fn run(args: &Args) -> Result<(), ViewError> {
    let report = write_view(&args.dir, args.scene.as_deref())?;
    println!("view {}", report.headline());
    for problem in &report.problems {
        eprintln!("warning: {}: {}", problem.file, problem.message);
    }
    if args.serve {
        serve(&report.dir, args.port)?;
    } else {
        println!(
            "open it with `karst-view {} --serve` (or any static server on that folder)",
            args.dir.display()
        );
    }
    Ok(())
}
